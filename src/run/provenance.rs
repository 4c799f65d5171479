//! What makes a `summary.json` traceable: the version, the commit, the scenario's SHA-256
//! and the process's peak memory.

use crate::scenario::Scenario;
use std::cell::Cell;
use std::path::{Path, PathBuf};

/// The peak resident set size of this process so far, MiB (`VmHWM` of `/proc/self/status`;
/// `None` where that file does not exist, i.e. off Linux). Written into every
/// `summary.json` as `peak_rss_mib`, with `peak_rss_scope`: `"run"` when it is the run's
/// own (a `softway run`, or a sweep's or ladder's run one at a time, the peak reset before
/// each to the process's size then, `reset_peak_rss`), `"process"` when runs ran
/// together and it bounds them all.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm(&status)
}

thread_local! {
    /// Whether the peak this thread's run writes into its summary is the process's, shared
    /// with runs at once ([`peak_rss_mib`]): set by a sweep around each run, on the thread
    /// that runs it and stamps its summary.
    static PEAK_SHARED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `run` with its summary's peak marked as the process's (`shared`) or as the run's
/// own; the mark is taken off after.
pub(crate) fn with_peak_scope<T>(shared: bool, run: impl FnOnce() -> T) -> T {
    let before = PEAK_SHARED.with(|s| s.replace(shared));
    let out = run();
    PEAK_SHARED.with(|s| s.set(before));
    out
}

/// Resets this process's peak resident set size to its present size (Linux's
/// `/proc/self/clear_refs`, value 5), so that the next [`peak_rss_mib`] is the peak since;
/// `false` where that cannot be done.
pub(crate) fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
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
            let scope = if PEAK_SHARED.with(Cell::get) {
                "process"
            } else {
                "run"
            };
            o.insert("peak_rss_scope".into(), scope.into());
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
/// [`crate::run::error::RunError::Output`].
pub fn write_scenario_copy<R>(
    sc: &crate::scenario::Scenario<R>,
    out: &Path,
) -> Result<PathBuf, crate::run::error::RunError> {
    let f = out.join(SCENARIO_COPY);
    crate::output::files::write_atomic(&f, sc.provenance_text().as_bytes())
        .map_err(|e| crate::run::error::RunError::output(&f, e))?;
    Ok(f)
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
