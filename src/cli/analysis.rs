//! The analysis subcommands: `modes`, `receptance`, `matrix`, `stability` (one function
//! each; the runs' subcommands are in [`super`]).

use super::{print_report, print_result, CommandResult, Replace};
use crate::build::resolve;
use crate::output::job::JobFolder;
use crate::run::Cancel;
use crate::scenario::Scenario;
use crate::time::sdof::analyse;
use std::path::{Path, PathBuf};

/// A kind's own study (`softway modes` of a wheel, `softway receptance` of a track:
/// [`crate::scenario::kind::Spec::study`]) into a staged folder: the scenario read (with the
/// `--set` overrides `set`), refused naming the kinds that answer `command` when its kind
/// does not, the folder staged under the folder rules, the study run, the folder finished
/// and marked (interrupted or not), the study's lines and files printed.
#[allow(clippy::too_many_arguments)]
pub(super) fn study_command(
    command: &str,
    scenario: &Path,
    set: &[String],
    count: Option<usize>,
    out: Option<PathBuf>,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    if count == Some(0) {
        return Err("--count 0: ask for at least one mode".into());
    }
    let sc = super::read_scenario(scenario, set)?;
    for w in &sc.warnings {
        errln!("softway: warning: {w}");
    }
    let Some(study) = sc.runs[0].model.study(command) else {
        let kinds = crate::scenario::kind::Registry::builtin().answering(command);
        return Err(format!(
            "{}: `softway {command}` needs a {} scenario (kind = \"{}\")",
            scenario.display(),
            kinds.join(" or "),
            kinds.join("\" or \""),
        )
        .into());
    };
    let out = match out {
        Some(out) => out,
        None => super::with_sets(super::default_out(&sc.name, command), set)?,
    };
    let stage = JobFolder::begin(command, &out, force, &[scenario])?;
    let opts = crate::scenario::kind::StudyOptions {
        count,
        plots: sc.plots,
        cancel: cancel.flag(),
    };
    let report = study.run(&sc, &opts, stage.dir())?;
    let interrupted = report.interrupted.is_some() || cancel.is_cancelled();
    let files = stage.finish(&report.files, Some(&sc), interrupted)?;
    print_report(
        Some(format!("{} ({})", sc.name, scenario.display())),
        &report.lines,
        &files,
        interrupted
            .then(|| {
                report
                    .interrupted
                    .as_deref()
                    .unwrap_or("interrupted")
                    .to_string()
            })
            .as_deref(),
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
    let stage = JobFolder::begin("matrix", &out, force, &[scenario])?;
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
            let stage = JobFolder::begin("stability", &dir, force, &[])?;
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
