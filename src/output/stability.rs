//! The stability report of the scheme: text table, CSV and plot.

use crate::output::files::write_atomic;
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::time::sdof::StabilityReport;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The comparison of the Coriolis treatments on the spinning oscillator as a text table.
pub fn gyroscopic_text(spin_h: f64, rows: &[crate::time::sdof::GyroscopicRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nspinning oscillator, Omega*h = {spin_h:e}: the Coriolis term in A (time.coriolis = \"implicit\") \
         against on the right-hand side at v0 + h a0 (\"extrapolated\")"
    );
    let _ = writeln!(
        s,
        "{:>12} {:>16} {:>16} {:>16} {:>16}",
        "omega0*h", "rho implicit", "rho extrapolated", "eigenvalue gap", "parasitic"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:>12.4e} {:>16.10} {:>16.10} {:>16.3e} {:>16.3e}",
            r.omega0_h, r.rho_implicit, r.rho_extrapolated, r.eigenvalue_gap, r.parasitic
        );
    }
    let worst = rows
        .iter()
        .map(|r| r.rho_extrapolated - r.rho_implicit.max(1.0))
        .fold(f64::NEG_INFINITY, f64::max);
    let _ = writeln!(
        s,
        "extrapolated spectral radius above max(implicit, 1) by at most {worst:.3e}"
    );
    s
}

/// The report as a text table for the terminal.
pub fn table_text(r: &StabilityReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "space-time scheme: alpha = {}, gamma = {}, beta = 1 - alpha/(1+gamma) = {:.6}",
        r.alpha, r.gamma, r.beta
    );
    let _ = writeln!(
        s,
        "{:>12} {:>16} {:>16} {:>16}",
        "omega*h", "spectral radius", "damping ratio", "period error"
    );
    for a in &r.table {
        let f = |x: f64| {
            if x.is_finite() {
                format!("{x:>16.6e}")
            } else {
                format!("{:>16}", "(real roots)")
            }
        };
        let _ = writeln!(
            s,
            "{:>12.4e} {:>16.10} {} {}",
            a.omega_h,
            a.spectral_radius,
            f(a.damping_ratio),
            f(a.period_error)
        );
    }
    let _ = writeln!(s, "high-frequency limit rho_inf = {:.6}", r.rho_inf);
    match r.stability_limit_omega_h {
        None => {
            let _ = writeln!(
                s,
                "unconditionally stable (spectral radius <= 1 for omega*h in 1e-6..1e8)"
            );
        }
        Some(l) => {
            let _ = writeln!(s, "conditionally stable: omega*h < {l:.6} (the time step must satisfy h < {l:.4} / omega_max)");
        }
    }
    s
}

/// Writes `stability.csv` and `stability.png` into `dir`.
///
/// # Errors
/// I/O or drawing errors.
pub fn write(r: &StabilityReport, dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let mut csv = super::csv::record([
        "omega_h",
        "spectral_radius",
        "damping_ratio",
        "period_error",
    ]);
    for a in &r.table {
        super::csv::push_record(
            &mut csv,
            [
                a.omega_h,
                a.spectral_radius,
                a.damping_ratio,
                a.period_error,
            ]
            .map(|x| format!("{x:e}")),
        );
    }
    let c = dir.join("stability.csv");
    write_atomic(&c, csv.as_bytes())?;
    let x: Vec<f64> = r.table.iter().map(|a| a.omega_h).collect();
    let title = format!(
        "alpha = {}, gamma = {}",
        crate::output::plot::sig(r.alpha, 6),
        crate::output::plot::sig(r.gamma, 6)
    );
    let mut p1 = Panel::new(
        format!("Spectral radius ({title})"),
        "omega h",
        "spectral radius",
    );
    p1.x_log = true;
    p1.series.push(Series::new(
        "spectral radius",
        x.clone(),
        r.table.iter().map(|a| a.spectral_radius).collect(),
        SeriesStyle::Line,
    ));
    p1.hlines.push((1.0, "1 (stability bound)".into()));
    let mut p2 = Panel::new(
        "Relative period error (T_num - T)/T",
        "omega h",
        "period error",
    );
    p2.x_log = true;
    p2.series.push(Series::new(
        "period error",
        x.clone(),
        r.table.iter().map(|a| a.period_error).collect(),
        SeriesStyle::Line,
    ));
    let mut p3 = Panel::new("Algorithmic damping ratio", "omega h", "damping ratio xi");
    p3.x_log = true;
    p3.series.push(Series::new(
        "damping ratio",
        x,
        r.table.iter().map(|a| a.damping_ratio).collect(),
        SeriesStyle::Line,
    ));
    for p in [&mut p2, &mut p3] {
        off_axis_bifurcation(p);
    }
    let png = dir.join("stability.png");
    panels(&png, &[p1, p2, p3], 3, 1, (1200, 1500))?;
    Ok(vec![c, png])
}

/// Where the eigenvalues turn real the phase nears pi and the period error and the damping
/// ratio of the last complex pair run off the trend of the others: on the log ladder of
/// `omega h` that is one point, which would set the axis and squeeze every other point
/// into a band (issue 48's class: a range set by one isolated point). When the last
/// defined point lies farther from the others' range than that range is wide, the axis is
/// set by the others, the line runs off it towards that point, and the note gives it.
fn off_axis_bifurcation(p: &mut Panel) {
    let Some(s) = p.series.first() else { return };
    let pts: Vec<(f64, f64)> =
        s.x.iter()
            .zip(&s.y)
            .filter(|(_, y)| y.is_finite())
            .map(|(&x, &y)| (x, y))
            .collect();
    let Some((&(x_last, y_last), rest)) = pts.split_last() else {
        return;
    };
    if rest.len() < 4 {
        return;
    }
    let (lo, hi) = rest
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, y)| {
            (a.min(y), b.max(y))
        });
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let beyond = (lo - y_last).max(y_last - hi);
    if beyond > span {
        let m = 0.08 * span;
        p.y_range = Some((lo - m, hi + m));
        p.note = format!(
            "Off the axis: {} at omega h = {}, the last point before the eigenvalues turn \
             real (their phase nears pi).",
            crate::output::plot::sig(y_last, 3),
            crate::output::plot::sig(x_last, 3)
        );
    }
}
