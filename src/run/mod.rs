//! Jobs: run a built [`Scenario`] (validated by [`crate::scenario`], its steps resolved by
//! [`crate::build::resolve`]) into [`Results`] in memory ([`run()`]), which
//! [`Results::save`] writes as files (`history.csv`, `summary.json`, plots, VTK); the
//! command line's `run` ([`run_scenario`]) does both, streaming the long tables into the
//! output folder as it goes so that a long run's memory stays flat.

pub(crate) mod compare;
pub(crate) mod converge;
pub mod grow;
pub(crate) mod matrix;
pub(crate) mod on_block;
pub mod results;
pub(crate) mod sweep;
pub(crate) mod track;
pub(crate) mod track_rolling;
pub mod wheel;

pub use crate::guard::GuardMode;
pub use crate::kinds::bar::run as bar;
pub use crate::linalg::team::{Par, Team};
pub use crate::output::table::{Column, Columns};
use crate::scenario::Scenario;
pub use converge::observed_orders;
pub use results::{FieldArray, FieldFrame, Fields, Results};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
pub use sweep::creep::{creepage_at, ladder_rows, LadderRow, MAX_ORDER, MIN_ORDER, TARGETS};
pub use sweep::{sweep, PointStatus, SweepError, SweepPoint};

/// Errors of a job.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The simulation failed.
    #[error("run `{run}`: {source}")]
    Simulation {
        /// Run label.
        run: String,
        /// Cause.
        source: crate::simulation::SimError,
    },
    /// The model could not be built from the input (mesh file, elements, supports).
    #[error("{path}: {message}")]
    Input {
        /// File at fault.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// Output could not be written.
    #[error("cannot write {path}: {message}")]
    Output {
        /// File or folder.
        path: PathBuf,
        /// Cause.
        message: String,
    },
}

impl RunError {
    pub(crate) fn input(path: &Path, e: impl std::fmt::Display) -> Self {
        RunError::Input {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }

    pub(crate) fn output(path: &Path, e: impl std::fmt::Display) -> Self {
        RunError::Output {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// A cancellation token: the caller keeps a clone and calls [`Cancel::cancel`] (the CLI
/// from its Ctrl-C handler); a job stops at its next step and keeps what it has. Clones
/// share one flag; a fresh token is not cancelled.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Cancels every job that holds a clone of this token; returns true if it already was.
    pub fn cancel(&self) -> bool {
        self.0.swap(true, Ordering::SeqCst)
    }

    /// True once [`Cancel::cancel`] was called on a clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The flag itself, as `Simulation::run` reads it.
    pub fn flag(&self) -> &AtomicBool {
        &self.0
    }
}

/// Options of a job.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show a progress bar (on a terminal).
    pub progress: bool,
    /// The threads of each run; `None` (the default): [`Par::current`] when the run starts,
    /// i.e. the rayon pool it is called in. Sweeps and convergence ladders run their runs
    /// side by side, each with [`Par::Seq`].
    pub par: Option<Par>,
    /// Stops the job at its next step (it then keeps what it has, `interrupted` set).
    pub cancel: Cancel,
    /// What the divergence guard does ([`crate::guard`]): stop the run (the default), or
    /// record where it diverged and go on (the comparison lab's rows).
    pub guard: GuardMode,
    /// A caller's view of the run's progress (steps done of the current run), for a caller
    /// that draws its own bar (the Python package's); `None` (the default): none kept.
    pub progress_watch: Option<ProgressWatch>,
}

/// The progress of a job as another thread sees it: the current run's label, its steps
/// done and its steps in all, updated as the run goes (every 256 steps or so). Clones share
/// one view; a fresh one has seen no run.
#[derive(Debug, Clone, Default)]
pub struct ProgressWatch(Arc<std::sync::Mutex<Option<indicatif::ProgressBar>>>);

impl ProgressWatch {
    /// A view that has seen no run yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The current run's `(label, steps done, steps)`; `None` before the first run starts.
    pub fn get(&self) -> Option<(String, u64, u64)> {
        let bar = self.0.lock().ok()?.clone()?;
        Some((bar.prefix(), bar.position(), bar.length().unwrap_or(0)))
    }

    /// Watches `bar` from now on (each run of a scenario starts its own).
    fn watch(&self, bar: &indicatif::ProgressBar) {
        if let Ok(mut b) = self.0.lock() {
            *b = Some(bar.clone());
        }
    }
}

impl RunOptions {
    /// What every run's simulation is set up with ([`crate::simulation::Settings`]): the
    /// threads ([`RunOptions::par`]) and the guard's mode.
    pub fn settings(&self) -> crate::simulation::Settings {
        crate::simulation::Settings {
            par: self.par(),
            guard: self.guard,
        }
    }

    /// The threads of a run: [`RunOptions::par`], or those of the caller's pool.
    pub fn par(&self) -> Par {
        self.par.unwrap_or_else(Par::current)
    }
}

/// What a job reports back.
#[derive(Debug, Clone, Default)]
pub struct RunReport {
    /// Lines for the screen summary.
    pub lines: Vec<String>,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// True if interrupted.
    pub interrupted: bool,
    /// Warnings for the user (the library prints nothing; the CLI prints these).
    pub warnings: Vec<String>,
}

/// Runs every run of the scenario and returns its results in memory: the summary, the
/// histories as named columns, the contact nodes, the fields ([`Results`]; nothing is
/// written). [`Results::save`] writes them as the command line does.
///
/// The run executes on the caller's thread and, with [`RunOptions::par`] of two threads or
/// more, a helper thread of each run's own ([`Team`]), which ends with the run. It stops at
/// the next step when [`RunOptions::cancel`] is cancelled ([`Results::interrupted`]).
///
/// # Errors
/// [`RunError`]: a model that cannot be built, a failed simulation.
pub fn run(scenario: &Scenario, options: &RunOptions) -> Result<Results, RunError> {
    record(scenario, options, None)
}

/// Runs every run of the scenario and writes the results into `out` (the command line's
/// `run`): [`run()`], with the history, the contact nodes and the traction history streamed
/// into `out` as the run goes (memory flat on a long run), then [`Results::save`].
///
/// # Errors
/// [`RunError`].
pub fn run_scenario(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    // A run that fails (the divergence guard, a singular step) or whose results cannot be
    // written names the scenario file too.
    let named = |e: RunError| match e {
        RunError::Simulation { .. } | RunError::Output { .. } => RunError::input(&sc.path, e),
        e => e,
    };
    let results = record(sc, opts, Some(out)).map_err(named)?;
    let mut files = results.save(out).map_err(named)?;
    files.push(write_scenario_copy(sc, out)?);
    Ok(RunReport {
        lines: results.lines,
        files,
        interrupted: results.interrupted,
        warnings: results.warnings,
    })
}

/// Runs the scenario's model; tables are streamed into `stream` when given.
fn record(sc: &Scenario, opts: &RunOptions, stream: Option<&Path>) -> Result<Results, RunError> {
    crate::kinds::record(sc, stream, opts)
}

/// The peak resident set size of this process so far, MiB (`VmHWM` of `/proc/self/status`;
/// `None` where that file does not exist, i.e. off Linux). Written into every
/// `summary.json` as `peak_rss_mib`: the process's peak, so in a sweep or a convergence
/// ladder, whose runs share one process, it bounds the runs that ran together up to then.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm(&status)
}

/// `VmHWM` (kB) of a `/proc/<pid>/status` text, in MiB.
fn parse_vm_hwm(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb / 1024.0)
}

/// Adds what makes a `summary.json` traceable to a JSON object: `softway_version` (the
/// crate's version), `softway_git_commit` ([`crate::GIT_COMMIT`], when built from a git
/// checkout) and `scenario_sha256` ([`Scenario::source_sha256`], the digest of the
/// scenario text as run, which the folder's `scenario.toml` holds); and `peak_rss_mib`
/// ([`peak_rss_mib`], where the system tells it), promised for every run: every kind's
/// summary is stamped here, after its run.
pub(crate) fn stamp_provenance(json: &mut serde_json::Value, sc: &Scenario) {
    if let Some(o) = json.as_object_mut() {
        if let Some(mib) = peak_rss_mib() {
            o.insert("peak_rss_mib".into(), mib.into());
        }
        o.insert(
            "softway_version".into(),
            env!("CARGO_PKG_VERSION").to_string().into(),
        );
        if let Some(c) = crate::GIT_COMMIT {
            o.insert("softway_git_commit".into(), c.into());
        }
        o.insert("scenario_sha256".into(), sc.source_sha256.clone().into());
    }
}

/// The name of the copy of the scenario each output folder keeps
/// ([`Scenario::provenance_text`]).
pub const SCENARIO_COPY: &str = "scenario.toml";

/// Writes the scenario's copy ([`SCENARIO_COPY`]) into the folder `out`; returns its path.
///
/// # Errors
/// [`RunError::Output`].
pub fn write_scenario_copy<R>(
    sc: &crate::scenario::Scenario<R>,
    out: &Path,
) -> Result<PathBuf, RunError> {
    let f = out.join(SCENARIO_COPY);
    crate::output::files::write_atomic(&f, sc.provenance_text().as_bytes())
        .map_err(|e| RunError::output(&f, e))?;
    Ok(f)
}

/// A progress bar over `len` steps (hidden when not on a terminal or not asked for by
/// [`RunOptions::progress`]), handed to [`RunOptions::progress_watch`] when there is one.
pub(crate) fn progress_bar(len: u64, label: &str, opts: &RunOptions) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !opts.progress || !std::io::stderr().is_terminal() {
        let pb = indicatif::ProgressBar::with_draw_target(
            Some(len),
            indicatif::ProgressDrawTarget::hidden(),
        );
        if let Some(w) = &opts.progress_watch {
            pb.set_prefix(label.to_string());
            w.watch(&pb);
        }
        return pb;
    }
    let pb = indicatif::ProgressBar::new(len);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix:>12} [{bar:40}] {pos}/{len} steps ({per_sec}, eta {eta}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb.set_prefix(label.to_string());
    if let Some(w) = &opts.progress_watch {
        w.watch(&pb);
    }
    pb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_rss_is_read_from_the_status_text() {
        let status = "Name:\tsoftway\nVmPeak:\t  20480 kB\nVmHWM:\t    5120 kB\nVmRSS:\t 4096 kB\n";
        assert_eq!(parse_vm_hwm(status), Some(5.0));
        assert_eq!(parse_vm_hwm("Name: x\n"), None);
        // On Linux the process's own peak is at least the memory it holds now. The kernel
        // batches the per-thread RSS counters, so two readings of a many-threaded test
        // process may differ by a few hundred kB either way: only the 64 MiB just touched
        // is asserted, with a margin for that batching.
        if peak_rss_mib().is_some() {
            let big = vec![1u8; 64 << 20];
            std::hint::black_box(&big);
            let after = peak_rss_mib().unwrap();
            assert!(after >= 63.0, "peak {after} MiB after touching 64 MiB");
        }
    }
}
