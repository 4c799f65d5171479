//! The study commands: `softway sweep` (a grid of `--set` values or the `[sweep]` table),
//! `softway converge` (a ladder of refinements) and `softway compare` (the bar's lab), with
//! their cost over every point.

use super::*;
use crate::scenario::overrides::Grid;

/// `softway sweep`: the scenario over the grid of `--set` values (or its `[sweep]` table).
pub(super) fn sweep_command(
    scenario: &Path,
    set: &[String],
    grid: crate::scenario::overrides::Grid,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    let sc = Scenario::from_file(scenario)?;
    let text = std::fs::read_to_string(scenario)
        .map_err(|e| format!("{}: cannot read the scenario: {e}", scenario.display()))?;
    let (keys, grid) = if set.is_empty() {
        default_sweep(&sc, scenario)?
    } else {
        (
            set.iter().map(|s| parse_set(s)).collect::<Result<_, _>>()?,
            grid,
        )
    };
    let points = crate::scenario::overrides::grid(&keys, grid)?;
    check_ladder_estimate(scenario, &text, &points, yes)?;
    let out = out.unwrap_or_else(|| super::default_out(&sc.name, "sweep"));
    set_threads("--jobs", jobs)?;
    let stage = JobFolder::begin("sweep", &out, force, &[scenario])?;
    let (points, files) = crate::run::sweep::sweep(scenario, &text, &points, stage.dir(), cancel)?;
    for p in &points {
        for w in &p.warnings {
            errln!("softway: warning: {}: {w}", p.label());
        }
    }
    let dirs: Vec<PathBuf> = points.iter().map(|p| stage.final_path(&p.dir)).collect();
    let files = stage.finish(&files, Some(&sc), cancel.is_cancelled())?;
    let names: Vec<&str> = keys.iter().map(|(k, _)| k.as_str()).collect();
    outln!(
        "{}: {} swept over {} points{}",
        sc.name,
        names.join(", "),
        points.len(),
        incomplete_note(&points)
    );
    print_table(&out.join("sweep.md"), &files);
    // A creepage sweep on a ladder: its creepages, orders and limits after the table.
    if let Ok(ladder) = std::fs::read_to_string(out.join("creep_ladder.md")) {
        let lines: Vec<String> = ladder.lines().map(String::from).collect();
        for l in crate::output::terminal::fit(&lines, 0, crate::output::terminal::WIDTH) {
            outln!("{l}");
        }
    }
    for (d, p) in dirs.iter().zip(&points) {
        if d.exists() {
            outln!("    {}/", d.display());
        } else {
            outln!("    {}/ ({})", d.display(), p.status);
        }
    }
    failed_points(scenario, &points)?;
    if cancel.is_cancelled() {
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

/// A sweep's key and its values (TOML literals).
type KeyValues = (String, Vec<String>);

/// The keys of the scenario's `[sweep]` table and how they combine: its key, and its
/// ladder's when given (the product of the two: every value on every rung). A ladder with
/// keys set with each rung (`ladder.with`) is written out as lists taken side by side
/// ([`Grid::Zip`]): every value of the sweep's key on every rung, each rung with its own
/// values of those keys.
fn default_sweep(
    sc: &Scenario<crate::scenario::RunSpec>,
    scenario: &Path,
) -> Result<(Vec<KeyValues>, Grid), String> {
    let sweep = sc.sweep.clone().ok_or_else(|| {
        format!(
            "{}: no [sweep] table and no --set KEY=V1,V2,...",
            scenario.display()
        )
    })?;
    Ok(match (&sc.sweep_ladder, sc.sweep_ladder_with.is_empty()) {
        (Some((key, rungs)), false) => {
            let (values, n) = (&sweep.1, rungs.len());
            let spread = |vs: &[String]| -> Vec<String> {
                values
                    .iter()
                    .flat_map(|_| vs.iter().cloned())
                    .collect::<Vec<_>>()
            };
            let mut keys = vec![
                (
                    sweep.0.clone(),
                    values
                        .iter()
                        .flat_map(|v| std::iter::repeat_n(v.clone(), n))
                        .collect(),
                ),
                (key.clone(), spread(rungs)),
            ];
            keys.extend(
                sc.sweep_ladder_with
                    .iter()
                    .map(|(k, vs)| (k.clone(), spread(vs))),
            );
            (keys, Grid::Zip)
        }
        _ => (
            std::iter::once(sweep)
                .chain(sc.sweep_ladder.clone())
                .collect(),
            Grid::Product,
        ),
    })
}

/// ` (N interrupted, M failed: ...)` after a sweep's count of points when some did not
/// complete, else nothing.
pub(super) fn incomplete_note(points: &[crate::run::sweep::SweepPoint]) -> String {
    use crate::run::sweep::PointStatus;
    let interrupted = points
        .iter()
        .filter(|p| p.status == PointStatus::Interrupted)
        .count();
    let failed = points
        .iter()
        .filter(|p| matches!(p.status, PointStatus::Failed(_)))
        .count();
    if interrupted + failed == 0 {
        return String::new();
    }
    format!(
        " ({interrupted} interrupted, {failed} failed: their rows say so in the status column, \
         their figures are left empty)"
    )
}

/// The error of a sweep some of whose points failed (exit 2, after the table is written):
/// how many, and the first one's value and message.
///
/// # Errors
/// When a point failed.
pub(super) fn failed_points(
    scenario: &Path,
    points: &[crate::run::sweep::SweepPoint],
) -> Result<(), String> {
    use crate::run::sweep::PointStatus;
    let failed: Vec<_> = points
        .iter()
        .filter_map(|p| match &p.status {
            PointStatus::Failed(m) => Some((p, m)),
            _ => None,
        })
        .collect();
    match failed.first() {
        None => Ok(()),
        Some((p, m)) => Err(format!(
            "{}: {} of {} points failed (the others are written; status column of sweep.csv); first: {}: {}",
            scenario.display(),
            failed.len(),
            points.len(),
            p.label(),
            m.replace(['\n', '\r'], " ")
        )),
    }
}

/// The scenario of a sweep, its text, and the keys with their values of `--set` (or of
/// its `[sweep]` table).
type SweepValues = (
    Scenario<crate::scenario::RunSpec>,
    String,
    Vec<(String, Vec<String>)>,
    Grid,
);

/// [`SweepValues`] of the scenario file at `scenario` (`how` for `--set`'s keys; the
/// `[sweep]` table's own otherwise).
pub(super) fn sweep_values(
    scenario: &Path,
    set: Vec<String>,
    how: Grid,
) -> Result<SweepValues, Box<dyn std::error::Error>> {
    let sc = Scenario::from_file(scenario)?;
    let text = std::fs::read_to_string(scenario)
        .map_err(|e| format!("{}: cannot read the scenario: {e}", scenario.display()))?;
    let (keys, how) = if set.is_empty() {
        default_sweep(&sc, scenario)?
    } else {
        (
            set.iter().map(|s| parse_set(s)).collect::<Result<_, _>>()?,
            how,
        )
    };
    Ok((sc, text, keys, how))
}

/// `softway converge`: the scenario over the refinement ladder of `--set`.
pub(super) fn converge_command(
    scenario: &Path,
    set: &str,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    let sc = Scenario::from_file(scenario)?;
    let text = std::fs::read_to_string(scenario)
        .map_err(|e| format!("{}: cannot read the scenario: {e}", scenario.display()))?;
    let (key, values) = parse_set(set)?;
    let points = crate::scenario::overrides::grid(
        &[(key.clone(), values.clone())],
        crate::scenario::overrides::Grid::Product,
    )?;
    check_ladder_estimate(scenario, &text, &points, yes)?;
    let out = out.unwrap_or_else(|| super::default_out(&sc.name, "converge"));
    set_threads("--jobs", jobs)?;
    let stage = JobFolder::begin("converge", &out, force, &[scenario])?;
    let (_, files, warnings, failed) =
        crate::run::converge::converge(scenario, &text, &key, &values, stage.dir(), cancel)?;
    for w in &warnings {
        errln!("softway: warning: {w}");
    }
    let files = stage.finish(&files, Some(&sc), cancel.is_cancelled())?;
    outln!(
        "{}: convergence of {key} over {} rungs",
        sc.name,
        values.len()
    );
    print_table(&out.join("converge.md"), &files);
    if let Some(f) = failed {
        return Err(format!(
            "{}: a rung failed (the table holds the rungs before it): {f}",
            scenario.display()
        )
        .into());
    }
    if cancel.is_cancelled() {
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

/// `softway compare`: the combinations of a bar scenario side by side.
pub(super) fn compare_command(
    scenario: &Path,
    set: &[String],
    out: Option<PathBuf>,
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    let sc = open_scenario(scenario, set, yes)?;
    let out = match out {
        Some(out) => out,
        None => super::with_sets(PathBuf::from("out").join(&sc.name), set)?,
    };
    let stage = JobFolder::begin("compare", &out, force, &[scenario])?;
    let opts = RunOptions {
        cancel: cancel.clone(),
        ..RunOptions::default()
    };
    let report = crate::run::compare::compare(&sc, stage.dir(), &opts)?;
    let interrupted = report.interrupted || cancel.is_cancelled();
    let files = stage.finish(&report.files, Some(&sc), interrupted)?;
    print_report(
        None,
        &report.lines,
        &files,
        interrupted.then_some("interrupted: the table holds the runs finished before"),
    )
}

/// [`check_estimate`] over a sweep or a ladder: every point validated, the costs summed.
pub(super) fn check_ladder_estimate(
    path: &Path,
    text: &str,
    points: &[Vec<crate::scenario::Override>],
    yes: bool,
) -> Result<(), String> {
    let mut total: Option<crate::build::Estimate> = None;
    for p in points {
        let at = p
            .iter()
            .map(|o| format!("{} = {}", o.key, o.value))
            .collect::<Vec<_>>()
            .join(", ");
        let sc = crate::scenario::overrides::read_with(
            text,
            path,
            p,
            &crate::kinds::Registry::builtin(),
        )
        .map_err(|e| e.to_string())
        .and_then(|(sc, _)| resolve(&sc).map_err(|e| e.to_string()))
        .map_err(|e| format!("{at}: {e}"))?;
        check_estimate(&sc, true)?;
        let e = crate::build::estimate(&sc, None);
        total = Some(match total {
            None => e,
            Some(mut t) => {
                t.steps += e.steps;
                t.seconds += e.seconds;
                t.disk_bytes += e.disk_bytes;
                t.memory_bytes = t.memory_bytes.max(e.memory_bytes);
                if e.dofs > t.dofs {
                    t.dofs = e.dofs;
                    t.culprit = e.culprit;
                }
                t
            }
        });
    }
    match total.and_then(|t| crate::output::job::admit(&t, yes)) {
        Some(why) => Err(format!("{}: the sweep: {why}", path.display())),
        None => Ok(()),
    }
}
