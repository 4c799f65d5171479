//! Jobs: run a built [`Scenario`] (validated by [`crate::scenario`], its steps resolved by
//! [`crate::build::resolve`]) and write its results (`history.csv`, `summary.json`, plots,
//! VTK) into an output folder.

pub mod bar;
pub mod compare;
pub mod converge;
pub mod sdof;
pub mod sweep;
pub mod wheel;

use crate::scenario::{Model, Scenario};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

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

/// Options of a job.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show a progress bar (on a terminal).
    pub progress: bool,
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
}

/// Set by Ctrl-C: the running job stops at the next step and writes what it has.
pub static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Runs every run of the scenario and writes the results into `out`.
///
/// # Errors
/// [`RunError`].
pub fn run_scenario(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    match &sc.runs[0].model {
        Model::Sdof(_) => sdof::run(sc, out, opts),
        Model::BarImpact(_) | Model::TwoBars(_) => bar::run(sc, out, opts),
        Model::Wheel(_) => wheel::run(sc, out, opts),
    }
}

/// Adds what makes a `summary.json` traceable to a JSON object: `softway_version` (the
/// crate's version) and `scenario_sha256` ([`Scenario::source_sha256`], the digest of the
/// scenario text as run).
pub(crate) fn stamp_provenance(json: &mut serde_json::Value, sc: &Scenario) {
    if let Some(o) = json.as_object_mut() {
        o.insert(
            "softway_version".into(),
            env!("CARGO_PKG_VERSION").to_string().into(),
        );
        o.insert("scenario_sha256".into(), sc.source_sha256.clone().into());
    }
}

/// A progress bar over `len` steps (hidden when not on a terminal or not asked for).
pub(crate) fn progress_bar(len: u64, label: &str, show: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !show || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
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
    pb
}
