//! The `softway` command line: parse, validate, call the library, report (the binary's
//! `main` calls [`main`]). A scenario goes through the library's three stages:
//! [`Scenario::from_file`] parses and validates it, [`resolve`] builds what needs a model
//! (the step from `cfl`), the jobs run it; the files are the output module's.

use crate::build::resolve;
use crate::output::job::JobFolder;
use clap::{Parser, Subcommand};

/// The file by which the command line marks a folder it wrote (it replaces only such
/// folders).
pub use crate::output::staging::MARKER;
use crate::run::{run_scenario, Cancel, Par, RunOptions};
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `println!` that never panics: a closed standard output (`softway run ... | head`) only
/// silences the rest of the report; the run itself goes on and its files are written.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// `eprintln!` that never panics (a closed standard error).
macro_rules! errln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod analysis;
mod set;
use set::parse_set;
mod study;
use study::{compare_command, converge_command, sweep_command};
mod shakedown;
mod shard;

use analysis::{matrix_command, stability_command, study_command};

/// Dynamic contact by the space-time finite element method (Bajer's soft way).
#[derive(Parser, Debug)]
#[command(name = "softway", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What may be replaced: an output folder of other files.
#[derive(clap::Args, Debug)]
struct Replace {
    /// Replace the output folder even if it holds files softway did not write (a folder
    /// written by softway is always replaced whole, never mixed with new files).
    #[arg(long)]
    force: bool,
}

/// What a run may do beyond the defaults: replace a folder of other files, exceed the
/// size limits.
#[derive(clap::Args, Debug)]
struct Guard {
    /// Replace the output folder even if it holds files softway did not write (a folder
    /// written by softway is always replaced whole, never mixed with new files).
    #[arg(long)]
    force: bool,
    /// Run even if the estimate of steps, time, memory or disk is beyond the limits (4 h on
    /// one core, half the memory, 20 GB of per-step files).
    #[arg(long)]
    yes: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scenario and write history.csv, summary.json, plots and fields into a folder.
    Run {
        /// The scenario file (TOML).
        scenario: PathBuf,
        /// KEY=VALUE: a dotted key of the scenario set to a TOML value for this run, e.g.
        /// rolling.speed_km_h=120, wheel.rim_nodes=576, contact.method=exact (nothing after
        /// `=` removes the key); repeatable. Checked as the file's keys are; the output
        /// folder's scenario.toml holds the text as run.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output folder [default: out/<scenario name>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Threads for the run [default: the number of cores]. A step matrix of 1,500
        /// dofs or more is solved in two parts side by side, and its right-hand side formed
        /// in as many parts as threads (at most the cores that other processes leave free),
        /// on the run's own helper threads; smaller ones on one thread. The results do not
        /// depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Whose factorizations and solves the step matrices get: "softway" (the tuned
        /// kernels) or "faer" (faer's own sparse LU and Cholesky, the reference they are
        /// checked and timed against; the same answers to rounding, summary.json says
        /// `"solver": "faer"`).
        #[arg(long, default_value = "softway", value_name = "SOLVER")]
        solver: crate::linalg::Backend,
        #[command(flatten)]
        guard: Guard,
    },
    /// A growth study: passes of the scenario's run, each over the surface profile the wear
    /// of the passes before left ([growth] and [wear] tables): spectra, growth rates, polygon
    /// orders; a checkpoint after every pass.
    Grow {
        /// The scenario file (TOML, kind = "wheel" with [growth] and [wear]).
        scenario: PathBuf,
        /// Simulated passes in all [default: the scenario's growth.passes].
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=100_000))]
        passes: Option<u64>,
        /// Go on from the output folder's checkpoint.json (same scenario text and --set).
        #[arg(long)]
        resume: bool,
        /// KEY=VALUE: a dotted key set to a TOML value, as `run --set`; repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output folder [default: out/<scenario name>-grow].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Threads of each pass [default: the number of cores].
        #[arg(long)]
        threads: Option<usize>,
        #[command(flatten)]
        guard: Guard,
    },
    /// Run a scenario over the values of one key or a grid of several, in parallel (e.g. the
    /// paper's Fig. 15).
    Sweep {
        /// The scenario file (TOML).
        scenario: PathBuf,
        /// KEY=V1,V2,... (a dotted scenario key and its values), e.g.
        /// rolling.speed_km_h=90,120,150; repeatable: a grid over several keys (--grid); a
        /// key with one value is set at every point. Default: the scenario's [sweep] table.
        #[arg(long = "set", value_name = "KEY=V1,V2,...")]
        set: Vec<String>,
        /// How the keys' values combine: every combination (product), or the i-th value of
        /// each key together (zip; lists of one length, a key with one value set at every
        /// point).
        #[arg(long, value_enum, default_value_t = crate::scenario::overrides::Grid::Product)]
        grid: crate::scenario::overrides::Grid,
        /// Output folder [default: out/<scenario name>-sweep].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Runs at once [default: the number of cores].
        #[arg(long)]
        jobs: Option<usize>,
        /// I/N: run only slice I of N of the grid's points (the k-th point, in the grid's
        /// order, when k mod N = I - 1; for a job array), into
        /// out/<scenario name>-sweep-shard-I-of-N by default; `softway gather` joins them.
        #[arg(long)]
        shard: Option<String>,
        #[command(flatten)]
        guard: Guard,
    },
    /// Join the folders of `softway sweep --shard I/N` (every I of one N) into the table and
    /// plot `softway sweep` writes.
    Gather {
        /// The shards' folders.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Output folder [default: out/<scenario name>-sweep].
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        replace: Replace,
    },
    /// Run a scenario over a refinement ladder of one key (mesh or step) and report the
    /// observed order of every key figure: converge.csv, converge.md, converge.png.
    Converge {
        /// The scenario file (TOML, one run).
        scenario: PathBuf,
        /// KEY=V1,V2,V3,... a geometric ladder of at least three rungs, e.g.
        /// wheel.rings=6,12,24 or time.h=0.1,0.05,0.025.
        #[arg(long)]
        set: String,
        /// Output folder [default: out/<scenario name>-converge].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Runs at once [default: the number of cores].
        #[arg(long)]
        jobs: Option<usize>,
        #[command(flatten)]
        guard: Guard,
    },
    /// Run the combinations (integrator, contact treatment, time step, mesh) of a bar
    /// scenario side by side against the exact answer: compare.csv, compare.md, force and
    /// energy plots.
    Compare {
        /// The scenario file (TOML, kind = "bar_impact" or "two_bars", one [[runs]] entry
        /// per combination).
        scenario: PathBuf,
        /// KEY=VALUE: a dotted key set to a TOML value, as `run --set`; repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output folder [default: out/<scenario name>].
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        guard: Guard,
    },
    /// Natural frequencies (Hz) and periods (us) of a wheel scenario's model, at rest and
    /// spinning (rotating frame), with the mode shapes as VTU.
    Modes {
        /// The scenario file (TOML, kind = "wheel").
        scenario: PathBuf,
        /// KEY=VALUE: a dotted key set to a TOML value, as `run --set`; repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Number of elastic modes.
        #[arg(long, default_value_t = 12)]
        count: usize,
        /// Output folder [default: out/<scenario name>-modes].
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        replace: Replace,
    },
    /// The rail's point receptance of a track scenario (mid-span and above a sleeper,
    /// magnitude and phase, 20 Hz-3 kHz by default) with its pinned-pinned, track and P2
    /// frequencies: receptance.csv, receptance.png, summary.json.
    Receptance {
        /// The scenario file (TOML, kind = "track").
        scenario: PathBuf,
        /// Output folder [default: out/<scenario name>-receptance].
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        replace: Replace,
    },
    /// Write the space-time step's matrices of a wheel, bar, press or 3D rolling scenario
    /// (Matrix Market) for other solvers, with the size of each factor and softway's time
    /// for one free step: A.mtx, B.mtx, K.mtx, u0/v0/f.mtx, fixed.txt, matrix.json
    /// (bench/peers/ reads them).
    Matrix {
        /// The scenario file (TOML, kind = "wheel", "bar_impact", "press" or "rolling3d"; its
        /// first run).
        scenario: PathBuf,
        /// Output folder [default: out/<scenario name>-matrix].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Free steps timed in each of the five rounds (the median round is reported)
        /// [default: 2,000,000 / nnz(A), between 20 and 20,000].
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
        steps: Option<u64>,
        #[command(flatten)]
        replace: Replace,
    },
    /// Spectral radius, damping and period error of the scheme against omega*h.
    Stability {
        /// alpha of Eq. (8), in (0, 1].
        #[arg(long, default_value_t = 0.8)]
        alpha: f64,
        /// gamma of Eq. (24), in [0, 1].
        #[arg(long, default_value_t = 0.0)]
        gamma: f64,
        /// Also write stability.csv and stability.png into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also compare the two treatments of the Coriolis term (`time.coriolis`) on the
        /// spinning oscillator at this spin times the step, Omega*h in (0, 0.1] (the
        /// wheel: 300 rad/s * 2 us = 6e-4).
        #[arg(long)]
        spin_h: Option<f64>,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        replace: Replace,
    },
    /// Johnson's rolling shakedown: a Hertz pressure moved pass after pass over a
    /// plane-strain elastic-perfectly-plastic half-space; the plastic strain increment per
    /// pass (shakedown.csv, residual.csv, shakedown.png with --out).
    Shakedown(shakedown::ShakedownArgs),
}

/// The command line's entry: parses the arguments, runs the subcommand, returns the exit
/// code (0 done, 1 a check failed, 2 an error, 130 interrupted).
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    // Ctrl-C cancels the jobs' token; a second one aborts.
    let cancel = Cancel::new();
    let on_ctrl_c = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        if on_ctrl_c.cancel() {
            std::process::exit(130);
        }
        errln!("\ninterrupted: finishing the current step and writing what was computed (Ctrl-C again to abort)");
    });
    match try_main(cli, &cancel) {
        Ok(code) => code,
        Err(e) => {
            // Never the staging folder (removed by now): the output folder asked for.
            errln!(
                "softway: error: {}",
                crate::output::staging::public_message(&e.to_string())
            );
            ExitCode::from(2)
        }
    }
}

/// What a subcommand returns: its exit code, or the error `main` reports.
pub(super) type CommandResult = Result<ExitCode, Box<dyn std::error::Error>>;

/// Runs the subcommand of `cli`, one function each.
fn try_main(cli: Cli, cancel: &Cancel) -> CommandResult {
    match cli.command {
        Command::Run {
            scenario,
            set,
            out,
            quiet,
            threads,
            solver,
            guard,
        } => run_command(
            &scenario,
            &set,
            out,
            (quiet, threads, solver),
            guard,
            cancel,
        ),
        Command::Grow {
            scenario,
            passes,
            resume,
            set,
            out,
            threads,
            guard,
        } => grow_command(&scenario, passes, resume, &set, out, threads, guard, cancel),
        Command::Sweep {
            scenario,
            set,
            grid,
            out,
            jobs,
            shard: Some(shard),
            guard,
        } => shard::shard_command(&scenario, set, grid, out, jobs, &shard, guard, cancel),
        Command::Sweep {
            scenario,
            set,
            grid,
            out,
            jobs,
            shard: None,
            guard,
        } => sweep_command(&scenario, &set, grid, out, jobs, guard, cancel),
        Command::Gather {
            shards,
            out,
            replace,
        } => shard::gather_command(&shards, out, replace, cancel),
        Command::Converge {
            scenario,
            set,
            out,
            jobs,
            guard,
        } => converge_command(&scenario, &set, out, jobs, guard, cancel),
        Command::Compare {
            scenario,
            set,
            out,
            guard,
        } => compare_command(&scenario, &set, out, guard, cancel),
        Command::Modes {
            scenario,
            set,
            count,
            out,
            replace,
        } => study_command("modes", &scenario, &set, Some(count), out, replace, cancel),
        Command::Receptance {
            scenario,
            out,
            replace,
        } => study_command("receptance", &scenario, &[], None, out, replace, cancel),
        Command::Matrix {
            scenario,
            out,
            steps,
            replace,
        } => matrix_command(&scenario, out, steps, replace, cancel),
        Command::Stability {
            alpha,
            gamma,
            out,
            spin_h,
            json,
            replace,
        } => stability_command(alpha, gamma, out, spin_h, json, replace, cancel),
        Command::Shakedown(args) => shakedown::shakedown_command(args, cancel),
    }
}

/// `softway run`: one scenario into its folder, with its report on standard output.
fn run_command(
    scenario: &Path,
    set: &[String],
    out: Option<PathBuf>,
    (quiet, threads, solver): (bool, Option<usize>, crate::linalg::Backend),
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    set_threads("--threads", threads)?;
    let sc = open_scenario(scenario, set, yes)?;
    let out = match out {
        Some(out) => out,
        None => with_sets(PathBuf::from("out").join(&sc.name), set)?,
    };
    let stage = JobFolder::begin("run", &out, force, &[scenario])?;
    let opts = RunOptions {
        progress: !quiet,
        par: threads.map(Par::threads),
        cancel: cancel.clone(),
        solver,
        ..RunOptions::default()
    };
    let report = run_scenario(&sc, stage.dir(), &opts)?;
    for w in &report.warnings {
        errln!("softway: warning: {w}");
    }
    // Interrupted when the run stopped before its last step: a signal that comes once the
    // steps are done (while the files are written) leaves complete results, whose summary
    // says so, and the command exits 0.
    let interrupted = report.interrupted;
    let files = stage.finish(&report.files, Some(&sc), interrupted)?;
    print_report(
        Some(format!("{} ({})", sc.name, scenario.display())),
        &report.lines,
        &files,
        interrupted.then_some("interrupted; the files above hold the steps computed so far"),
    )
}

/// `softway grow`: a growth study into its folder, a line per pass, its summary at the end.
/// The study's folder is claimed under the rules of every command (a new study: the folder
/// rules of [`JobFolder`]; `--resume`: a folder softway wrote) and written in place, so
/// that its checkpoint survives the process; its cost (every pass and the reference pass)
/// is checked before anything is written.
#[allow(clippy::too_many_arguments)]
fn grow_command(
    scenario: &Path,
    passes: Option<u64>,
    resume: bool,
    set: &[String],
    out: Option<PathBuf>,
    threads: Option<usize>,
    Guard { force, yes }: Guard,
    cancel: &Cancel,
) -> CommandResult {
    use crate::output::job::StudyFolder;
    use crate::output::terminal::quantity;
    set_threads("--threads", threads)?;
    let sc = resolve(&read_scenario(scenario, set)?)?;
    for w in &sc.warnings {
        errln!("softway: warning: {w}");
    }
    let Some(growth) = &sc.growth else {
        return Err(crate::run::RunError::input(
            scenario,
            "no [growth] table: softway grow needs [growth] and [wear] (the book, docs/src/growth.md)",
        )
        .into());
    };
    // The whole study: every pass and the reference pass, each a run of the scenario.
    let target = passes.map_or(growth.passes, |p| p as usize);
    let runs = target + usize::from(growth.reference);
    let est = estimate_of(&sc)?.repeated(runs as f64);
    if let Some(why) = crate::output::job::admit(&est, yes) {
        return Err(format!(
            "{}: the growth study ({runs} passes): {why}",
            sc.path.display()
        )
        .into());
    }
    let out = match out {
        Some(out) => out,
        None => with_sets(default_out(&sc.name, "grow"), set)?,
    };
    let opts = crate::run::grow::GrowOptions {
        passes: passes.map(|p| p as usize),
        resume,
        plots: sc.plots,
        par: threads.map(Par::threads).unwrap_or_else(Par::current),
    };
    // The study built and checked (its model, its keys against its grid) before its folder
    // is claimed: bad input writes nothing.
    let study = crate::run::grow::Study::prepare(&sc, &opts)?;
    let folder = if resume {
        StudyFolder::resume(&out, &[scenario])?
    } else {
        StudyFolder::fresh("grow", &out, force, &[scenario])?
    };
    outln!(
        "{} ({}): growth study into {}",
        sc.name,
        scenario.display(),
        out.display()
    );
    let report = study.run(&folder.path, cancel, |l| {
        let force = l
            .scalars
            .iter()
            .find(|s| s.0 == "mean_force_n")
            .map(|s| format!(", mean force {}", quantity(s.1, "N")))
            .unwrap_or_default();
        outln!(
            "  pass {}/{}: RMS roughness {:.5} um, uniform loss {}{force}, {}",
            l.pass + 1,
            l.target,
            l.rms * 1e6,
            quantity(l.uniform_loss, "m"),
            quantity(l.wall_s, "s")
        );
    })?;
    let interrupted = report.interrupted || cancel.is_cancelled();
    if interrupted {
        folder.mark_interrupted()?;
    } else {
        folder.mark_finished()?;
    }
    // `--resume` is advised only where there is a checkpoint to go on from: a study writes
    // one once its reference pass (if any) is done, none when stopped before.
    let resumable = folder.path.join(crate::growth::CHECKPOINT).is_file();
    print_report(
        Some(format!("{} ({})", sc.name, scenario.display())),
        &crate::run::grow::summary_lines(&report.summary),
        &report.files,
        interrupted.then_some(if resumable {
            "interrupted; the finished passes are kept: go on with --resume"
        } else {
            "interrupted before a pass finished: nothing to go on from; run the study again (without --resume)"
        }),
    )
}

/// The default output folder of a command that adds `suffix` to the scenario's name:
/// `out/<name>-<suffix>` (`out/wheel-converge`), the suffix's first word not doubled: a
/// scenario named `wheel-sweep` sweeps into `out/wheel-sweep`, not `out/wheel-sweep-sweep`.
pub(super) fn default_out(name: &str, suffix: &str) -> PathBuf {
    let word = suffix.split('-').next().unwrap_or(suffix);
    let stem = name
        .strip_suffix(&format!("-{word}"))
        .filter(|s| !s.is_empty())
        .unwrap_or(name);
    PathBuf::from("out").join(format!("{stem}-{suffix}"))
}

/// The default folder `base` of a command given `--set` values: `base,<key>=<value>,...`
/// (the values as a sweep names its points), so that a one-off change never replaces the
/// folder of the scenario as written (`softway run scenarios/wheel.toml --set
/// wheel.rim_nodes=576` writes `out/wheel,wheel.rim_nodes=576/`, not `out/wheel/`). A name
/// longer than a folder's name may be is refused, asking for `--out`.
pub(super) fn with_sets(base: PathBuf, set: &[String]) -> Result<PathBuf, String> {
    if set.is_empty() {
        return Ok(base);
    }
    let sets = set
        .iter()
        .map(|s| crate::scenario::Override::parse(s))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let name = format!(
        "{},{}",
        base.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        crate::run::sweep::point_dir_name(&sets)
    );
    if name.len() > crate::output::staging::NAME_MAX {
        return Err(format!(
            "--set: the default output folder `{name}` would have a name of {} bytes, more than the {} a folder's name may have: give --out DIR",
            name.len(),
            crate::output::staging::NAME_MAX
        ));
    }
    Ok(base.with_file_name(name))
}

/// The exit code of a command that finished its work: 130 when a signal (SIGINT, SIGTERM,
/// SIGHUP) came during it (its folder is then marked interrupted), else 0.
pub(super) fn exit_code(interrupted: bool) -> ExitCode {
    if interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    }
}

/// Prints `head` (if any), a job's report `lines` and the `files` it wrote (indented under
/// the head), then returns the exit code: 130 after the message `interrupted` when the job
/// was interrupted, else 0.
pub(super) fn print_report(
    head: Option<String>,
    lines: &[String],
    files: &[PathBuf],
    interrupted: Option<&str>,
) -> CommandResult {
    let (line, wrote, file) = if head.is_some() {
        ("  ", "  ", "    ")
    } else {
        ("", "", "  ")
    };
    if let Some(h) = head {
        for l in crate::output::terminal::wrap(&h, crate::output::terminal::WIDTH, 2) {
            outln!("{l}");
        }
    }
    for l in crate::output::terminal::fit(lines, line.len(), crate::output::terminal::WIDTH) {
        outln!("{line}{l}");
    }
    outln!("{wrote}wrote:");
    for f in files {
        outln!("{file}{}", f.display());
    }
    if let Some(message) = interrupted {
        errln!("softway: {message}");
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

/// The scenario at `path` with the `--set` overrides `set` (`KEY=VALUE` each) written into
/// it, validated and resolved, its estimate checked (`--yes` lets it past the limits) and
/// its warnings printed.
fn open_scenario(
    path: &Path,
    set: &[String],
    yes: bool,
) -> Result<Scenario, Box<dyn std::error::Error>> {
    let sc = resolve(&read_scenario(path, set)?)?;
    check_estimate(&sc, yes)?;
    for w in &sc.warnings {
        errln!("softway: warning: {w}");
    }
    Ok(sc)
}

/// The scenario at `path`, validated, with the `--set` overrides `set` (`KEY=VALUE` each)
/// written into it.
pub(super) fn read_scenario(
    path: &Path,
    set: &[String],
) -> Result<Scenario<crate::scenario::RunSpec>, Box<dyn std::error::Error>> {
    let sets = set
        .iter()
        .map(|s| crate::scenario::Override::parse(s))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Scenario::from_file_with(path, &sets)?)
}

/// Refuses a built scenario whose estimated cost is beyond [`crate::build::Limits`]
/// unless `yes`; a wheel's Gmsh mesh is read here (so that its errors come before any
/// output folder is made).
fn check_estimate(sc: &crate::scenario::Scenario, yes: bool) -> Result<(), String> {
    let est = estimate_of(sc)?;
    match crate::output::job::admit(&est, yes) {
        Some(why) => Err(format!("{}: {why}", sc.path.display())),
        None => Ok(()),
    }
}

/// The estimated cost of a built scenario's runs ([`crate::build::estimate`]); a wheel's
/// Gmsh mesh is read here (so that its errors come before any output folder is made).
fn estimate_of(sc: &crate::scenario::Scenario) -> Result<crate::build::Estimate, String> {
    let mut mesh_nodes = None;
    for run in &sc.runs {
        if let Some(n) = run.model.mesh_nodes(&sc.path).map_err(|e| e.to_string())? {
            mesh_nodes = Some(n);
        }
    }
    Ok(crate::build::estimate(sc, mesh_nodes))
}

/// A command-line mistake on one line (clap's message, its tip and the usage), exit 2;
/// `--help` and `--version` as clap prints them, exit 0.
fn usage_error(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            errln!("softway: error: no command given: softway run|sweep|gather|converge|compare|modes|receptance|matrix|stability ... (see softway --help)");
            return ExitCode::from(2);
        }
        _ => {}
    }
    let text = e.render().to_string();
    let mut parts = Vec::new();
    let mut usage = None;
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(u) = line.strip_prefix("Usage:") {
            usage = Some(u.trim().to_string());
        } else if !line.starts_with("For more information") {
            parts.push(line.to_string());
        }
    }
    let mut msg = parts.join(" ");
    if let Some(u) = usage {
        msg.push_str(&format!("; usage: {u}"));
    }
    errln!("softway: {msg}");
    ExitCode::from(2)
}

/// The most threads `--threads` and `--jobs` take.
const MAX_THREADS: usize = 256;

/// Threads of the pool: runs at once for `sweep` and `converge` (`--jobs`), threads of one
/// run (`--threads`); default: the number of cores.
/// At most [`MAX_THREADS`].
fn set_threads(flag: &str, threads: Option<usize>) -> Result<(), String> {
    match threads {
        Some(0) => Err(format!("{flag} 0: give at least one")),
        Some(j) if j > MAX_THREADS => {
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            Err(format!(
                "{flag} {j}: at most {MAX_THREADS} (this machine has {cores} cores; more threads than cores only wait for them)"
            ))
        }
        Some(j) => {
            rayon::ThreadPoolBuilder::new()
                .num_threads(j)
                .build_global()
                .ok();
            Ok(())
        }
        None => Ok(()),
    }
}

/// Writes `text`, a command's result (`stability`'s table or JSON, `modes`' tables), to
/// standard output and flushes it: a failed write (a full disk: `> /dev/full`) is an error
/// (exit 2), not an empty file and exit 0. A closed pipe (`| head`) is not: the reader
/// stopped reading. The reports of the commands that write folders stay best effort
/// ([`outln!`]): their results are the files.
pub(super) fn print_result(text: &str) -> Result<(), String> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write the result to standard output: {e}"))
        }
        _ => Ok(()),
    }
}

/// Prints a markdown table written by a study, laid out for the terminal
/// ([`crate::output::terminal::fit`]: within 100 columns, in readable units), and the files
/// it wrote.
fn print_table(md: &std::path::Path, files: &[PathBuf]) {
    let text = std::fs::read_to_string(md).unwrap_or_default();
    let lines: Vec<String> = text.lines().map(String::from).collect();
    for l in crate::output::terminal::fit(&lines, 0, crate::output::terminal::WIDTH) {
        outln!("{l}");
    }
    outln!("  wrote:");
    for f in files {
        outln!("    {}", f.display());
    }
}
