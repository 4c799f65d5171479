//! `softway sweep --shard I/N` and `softway gather`: a sweep in slices on a cluster's job
//! array (any grid of `softway sweep`: one key, or several by product or zip), joined into
//! the table and plot of `softway sweep` ([`crate::run::sweep::shard`]).

use super::study::{check_ladder_estimate, sweep_values};
use super::{print_table, set_threads, CommandResult, Guard, Replace};
use crate::output::job::JobFolder;
use crate::run::sweep::shard::{gather, read_manifest, run_shard, Shard, MANIFEST};
use crate::run::Cancel;
use crate::scenario::overrides::Grid;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `softway sweep --shard I/N`: slice `I` of the sweep's grid (one key or several,
/// `--grid product` or `zip`) into its own folder with its manifest. Every point of the
/// whole sweep is validated first, as `softway sweep` does, so a bad value fails every
/// slice at once rather than one of them at the end.
#[allow(clippy::too_many_arguments)]
pub(super) fn shard_command(
    scenario: &Path,
    set: Vec<String>,
    how: Grid,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    shard: &str,
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    let shard: Shard = shard.parse()?;
    let (sc, text, keys, how) = sweep_values(scenario, set, how)?;
    let points = crate::scenario::overrides::grid(&keys, how)?;
    check_ladder_estimate(scenario, &text, &points, yes)?;
    let out = out.unwrap_or_else(|| {
        super::default_out(
            &sc.name,
            &format!("sweep-shard-{}-of-{}", shard.index, shard.count),
        )
    });
    set_threads("--jobs", jobs)?;
    let stage = JobFolder::begin("shard", &out, force, &[scenario])?;
    let (mine, files) = run_shard(
        scenario,
        &text,
        &sc.name,
        &keys,
        how,
        shard,
        stage.dir(),
        cancel,
    )?;
    for p in &mine {
        for w in &p.warnings {
            errln!("softway: warning: {}: {w}", p.label());
        }
    }
    let files = stage.finish(&files, Some(&sc), cancel.is_cancelled())?;
    let names: Vec<&str> = keys.iter().map(|(k, _)| k.as_str()).collect();
    outln!(
        "{}: {}, shard {}/{}: {} of {} points{}",
        sc.name,
        names.join(", "),
        shard.index,
        shard.count,
        mine.len(),
        points.len(),
        super::study::incomplete_note(&mine)
    );
    if mine.is_empty() {
        outln!("  (no point falls in this shard)");
        for f in &files {
            outln!("    {}", f.display());
        }
    } else {
        print_table(&out.join("sweep.md"), &files);
    }
    super::study::failed_points(scenario, &mine)?;
    if cancel.is_cancelled() {
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

/// `softway gather`: the shards' folders into the sweep's table and plot.
pub(super) fn gather_command(
    shards: &[PathBuf],
    out: Option<PathBuf>,
    Replace { force }: Replace,
    cancel: &Cancel,
) -> CommandResult {
    // The default folder is named after the scenario, which the first manifest gives.
    let first = read_manifest(shards.first().ok_or("no shard folder given")?)?;
    let out = out.unwrap_or_else(|| super::default_out(&first.name, "sweep"));
    // The shards' folders are inputs: never replaced by the gathered one.
    let manifests: Vec<PathBuf> = shards.iter().map(|d| d.join(MANIFEST)).collect();
    let keep: Vec<&Path> = manifests.iter().map(PathBuf::as_path).collect();
    let stage = JobFolder::begin("sweep", &out, force, &keep)?;
    let (m, points, files) = gather(shards, stage.dir())?;
    // Gathering is quick: a signal during it stops the command after the writing.
    let interrupted = cancel.is_cancelled();
    let files = stage.finish(
        &files,
        None::<&crate::scenario::Scenario<crate::scenario::RunSpec>>,
        interrupted,
    )?;
    outln!(
        "{}: {} swept over {} points, gathered from {} shards{}",
        m.name,
        m.key_names(),
        points.len(),
        m.of,
        super::study::incomplete_note(&points)
    );
    print_table(&out.join("sweep.md"), &files);
    for p in &points {
        outln!("    {}/", p.dir.display());
    }
    super::study::failed_points(&shards[0], &points)?;
    Ok(super::exit_code(interrupted))
}
