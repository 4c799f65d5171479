//! The analysis subcommands: `modes`, `receptance`, `matrix`, `stability` (one function
//! each; the runs' subcommands are in [`super`]).

use super::{print_report, print_result, CommandResult, Replace};
use crate::build::resolve;
use crate::output::job::JobFolder;
use crate::run::Cancel;
use crate::scenario::Scenario;
use crate::time::sdof::analyse;
use std::path::{Path, PathBuf};

/// `softway modes`: a wheel's modes at rest and spinning, the shapes written as VTU and
/// drawn in `modes.png`.
pub(super) fn modes_command(
    scenario: &Path,
    set: &[String],
    count: usize,
    out: Option<PathBuf>,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    let sc = super::read_scenario(scenario, set)?;
    let Some(ws) = sc.runs[0].model.get::<crate::scenario::WheelScenario>() else {
        return Err(format!(
            "{}: `softway modes` needs a wheel scenario (kind = \"wheel\")",
            scenario.display()
        )
        .into());
    };
    if count == 0 {
        return Err("--count 0: ask for at least one mode".into());
    }
    let wm = crate::kinds::wheel::run::build(ws, &sc.path)?;
    let out = match out {
        Some(out) => out,
        None => super::with_sets(super::default_out(&sc.name, "modes"), set)?,
    };
    let stage = JobFolder::begin(&out, force, &[scenario])?;
    let rep = crate::modes::modes_report(&wm, count)?;
    let mut files = crate::modes::write_mode_shapes(&wm, &rep.at_rest, stage.dir())?;
    if sc.plots {
        files.extend(crate::modes::write_modes_figure(&wm, &rep, stage.dir())?);
    }
    // The modes are one solve: a signal during it stops the command after the writing.
    let interrupted = cancel.is_cancelled();
    let files = stage.finish(&files, Some(&sc), interrupted)?;
    let mut text = modes_text(&sc.name, &rep, &wm.spec.support, ws.spec.omega);
    text.push_str(&format!(
        "wrote {} files into {}\n",
        files.len(),
        out.display()
    ));
    print_result(&text)?;
    Ok(super::exit_code(interrupted))
}

/// The tables of `softway modes`: the rest modes, the spinning ones, the notes.
fn modes_text(
    name: &str,
    rep: &crate::modes::ModesReport,
    support: &crate::bodies::wheel::Support,
    omega: f64,
) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let support = match support {
        crate::bodies::wheel::Support::Hub { radius } => format!("a hub clamped within {radius} m"),
        crate::bodies::wheel::Support::CentrePinned => "the centre node pinned".to_string(),
    };
    let _ = writeln!(
        s,
        "{}: {} dofs ({} free), support: {support}",
        name, rep.dofs, rep.free_dofs
    );
    let _ = writeln!(s, "at rest:");
    let _ = writeln!(
        s,
        "{:>5} {:>14} {:>12} {:>5}  kind",
        "mode", "frequency Hz", "period us", "n"
    );
    for (i, m) in rep.at_rest.iter().enumerate() {
        let _ = writeln!(
            s,
            "{:>5} {:>14.2} {:>12.3} {:>5}  {}",
            i + 1,
            m.frequency_hz,
            m.period_us,
            m.wavenumber
                .map(|n| n.to_string())
                .unwrap_or_else(|| "-".into()),
            m.kind
        );
    }
    if let Some(sp) = &rep.spinning {
        let _ = writeln!(
            s,
            "spinning at omega = {} rad/s (frequencies in the wheel's rotating frame):",
            omega
        );
        let _ = writeln!(
            s,
            "{:>5} {:>14} {:>14} {:>10}  kind",
            "mode", "frequency Hz", "at rest Hz", "whirl"
        );
        for (i, m) in sp.iter().enumerate() {
            let _ = writeln!(
                s,
                "{:>5} {:>14.2} {:>14.2} {:>10}  {}",
                i + 1,
                m.frequency_hz,
                m.rest_frequency_hz,
                m.whirl.to_string(),
                m.kind
            );
        }
    }
    for n in &rep.notes {
        let _ = writeln!(s, "note: {n}");
    }
    s
}

/// `softway receptance`: a track's receptance and frequencies into a folder.
pub(super) fn receptance_command(
    scenario: &Path,
    out: Option<PathBuf>,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    let sc = Scenario::from_file(scenario)?;
    if sc.runs[0]
        .model
        .get::<crate::scenario::TrackScenario>()
        .is_none()
    {
        return Err(format!(
            "{}: `softway receptance` needs a track scenario (kind = \"track\")",
            scenario.display()
        )
        .into());
    }
    for w in &sc.warnings {
        errln!("softway: warning: {w}");
    }
    let out = out.unwrap_or_else(|| super::default_out(&sc.name, "receptance"));
    let stage = JobFolder::begin(&out, force, &[scenario])?;
    let report =
        crate::kinds::track::moving::receptance_job(&sc, stage.dir(), sc.plots, cancel.flag())?;
    let interrupted = report.interrupted || cancel.is_cancelled();
    let files = stage.finish(&report.files, Some(&sc), interrupted)?;
    print_report(
        Some(format!("{} ({})", sc.name, scenario.display())),
        &report.lines,
        &files,
        interrupted.then_some("interrupted: receptance.csv holds the frequencies computed so far"),
    )
}

/// `softway matrix`: the step's matrices of a scenario's first run, and softway's time.
pub(super) fn matrix_command(
    scenario: &Path,
    out: Option<PathBuf>,
    steps: Option<u64>,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    let sc = resolve(&Scenario::from_file(scenario)?)?;
    let out = out.unwrap_or_else(|| super::default_out(&sc.name, "matrix"));
    let stage = JobFolder::begin(&out, force, &[scenario])?;
    let (rep, files) =
        crate::run::matrix::dump(&sc, stage.dir(), steps.map(|s| s as usize), cancel.flag())?;
    let interrupted = cancel.is_cancelled();
    let files = stage.finish(&files, Some(&sc), interrupted)?;
    let mut lines: Vec<String> = rep
        .factor_nnz
        .iter()
        .map(|(name, nnz)| format!("nnz of the factors, {name}: {nnz}"))
        .collect();
    lines.push(format!("softway free step: {:.1} us", rep.softway_step_us));
    let head = format!(
        "{}: {} dofs, nnz(A) = {}, symmetric: {}; softway factors it as {}",
        sc.name, rep.n, rep.nnz_a, rep.symmetric, rep.factor
    );
    print_report(
        Some(head),
        &lines,
        &files,
        interrupted
            .then_some("interrupted: the matrices are written whole, the timing may be short"),
    )
}

/// `softway stability`: the scheme's stability table, optionally written and with the
/// Coriolis treatments compared.
pub(super) fn stability_command(
    alpha: f64,
    gamma: f64,
    out: Option<PathBuf>,
    spin_h: Option<f64>,
    json: bool,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    if let Some(s) = spin_h {
        if !(s.is_finite() && s > 0.0 && s <= 0.1) {
            return Err(format!(
                "--spin-h {s}: Omega*h must be in (0, 0.1] (the spin times the step)"
            )
            .into());
        }
    }
    let gyro = spin_h.map(|s| crate::time::sdof::gyroscopic_table(alpha, gamma, s, 5));
    if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
        return Err(format!("--alpha {alpha}: alpha must be in (0, 1] (Eq. 8)").into());
    }
    if !(gamma.is_finite() && (0.0..=1.0).contains(&gamma)) {
        return Err(format!("--gamma {gamma}: gamma must be in [0, 1] (Eq. 24)").into());
    }
    let rep = analyse(alpha, gamma, 5);
    let files = match out {
        Some(dir) => {
            let stage = JobFolder::begin(&dir, force, &[])?;
            let files = crate::output::stability::write(&rep, stage.dir())?;
            stage.finish(
                &files,
                None::<&Scenario<crate::scenario::RunSpec>>,
                cancel.is_cancelled(),
            )?
        }
        None => Vec::new(),
    };
    if json {
        let j = serde_json::json!({
            "alpha": rep.alpha, "gamma": rep.gamma, "beta": rep.beta,
            "rho_inf": rep.rho_inf,
            "unconditionally_stable": rep.unconditionally_stable,
            "stability_limit_omega_h": rep.stability_limit_omega_h,
            "table": rep.table,
            "spin_h": spin_h,
            "gyroscopic": gyro,
        });
        print_result(&format!("{}\n", serde_json::to_string_pretty(&j)?))?;
    } else {
        let mut text = crate::output::stability::table_text(&rep);
        if let (Some(s), Some(g)) = (spin_h, &gyro) {
            text.push_str(&crate::output::stability::gyroscopic_text(s, g));
        }
        for f in files {
            text.push_str(&format!("wrote {}\n", f.display()));
        }
        print_result(&text)?;
    }
    Ok(super::exit_code(cancel.is_cancelled()))
}
