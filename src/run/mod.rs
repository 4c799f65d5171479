//! Jobs: run a built [`Scenario`] (validated by [`crate::scenario`], its steps resolved by
//! [`crate::build::resolve`]) into [`Results`] in memory ([`run()`]), which
//! [`Results::save`] writes as files (`history.csv`, `summary.json`, plots, VTK); the
//! command line's `run` ([`run_scenario`]) does both, streaming the long tables into the
//! output folder as it goes so that a long run's memory stays flat.

pub(crate) mod compare;
pub(crate) mod converge;
pub(crate) mod error;
pub mod grow;
pub(crate) mod history;
pub(crate) mod matrix;
pub(crate) mod options;
pub(crate) mod provenance;
pub mod results;
pub(crate) mod sweep;

pub use crate::guard::GuardMode;
pub use crate::kinds::bar::run as bar;
pub use crate::kinds::wheel::run as wheel;
pub use crate::linalg::team::{Par, Team};
pub use crate::output::save::{claim_folder, save_files};
pub use crate::output::table::{Column, Columns};
use crate::scenario::Scenario;
pub use converge::observed_orders;
pub use error::RunError;
pub use options::{Cancel, ProgressWatch, RunOptions};
pub use provenance::{peak_rss_mib, write_scenario_copy, SCENARIO_COPY};
pub use results::{FieldArray, FieldFrame, Fields, Results};
use std::path::{Path, PathBuf};
pub use sweep::creep::{creepage_at, ladder_rows, LadderRow, MAX_ORDER, MIN_ORDER, TARGETS};
pub use sweep::{
    check_points, column_name, key_column, point_dir_name, sweep, PointRefused, PointStatus,
    SweepError, SweepPoint, COLUMN_NAMES, KEY_UNITS,
};

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
    let mut r = sc.runs[0].model.record(sc, stream, opts)?;
    // The reference solver's results are the same to rounding, not to the bit: said.
    if opts.solver != crate::linalg::Backend::Softway {
        if let Some(o) = r.summary.as_object_mut() {
            o.insert("solver".into(), opts.solver.name().into());
        }
    }
    Ok(r)
}
