//! The history table of a scenario's runs keyed by the run's label (the oscillator's, the
//! bars', the track's).

use crate::output::table::{Columns, Rows};
use crate::run::error::RunError;
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

/// The history of a scenario's runs, one row every `history_stride` steps keyed by the
/// run's label, with the columns `columns` (name, unit): streamed to `stream/history.csv`
/// when given, else held, with room reserved for every run's rows. Returns the table and
/// the path its errors name.
///
/// # Errors
/// [`RunError`] when the file cannot be created.
pub(crate) fn keyed_history(
    sc: &Scenario,
    stream: Option<&Path>,
    columns: &[(&str, &str)],
) -> Result<(Rows, PathBuf), RunError> {
    let hist = stream.map(|out| out.join("history.csv"));
    let labels = sc.runs.iter().map(|r| r.label.clone()).collect();
    let rows: usize = sc
        .runs
        .iter()
        .map(|r| (r.t_end / r.params.h).round() as usize / sc.history_stride.max(1) + 1)
        .sum();
    let name = hist.clone().unwrap_or_else(|| "history.csv".into());
    let csv = Rows::open(
        Columns::keyed("run", labels, columns),
        hist.as_deref(),
        rows,
    )
    .map_err(|e| RunError::output(&name, e))?;
    Ok((csv, name))
}
