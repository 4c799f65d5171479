//! The one output path of every command (`run`, `sweep` and its shards, `gather`,
//! `converge`, `compare`, `grow`, `modes`, `receptance`, `matrix`, `stability`,
//! `shakedown`): the promises a user relies on are made here once, not per command.
//!
//! - **The folder rules** ([`crate::output::staging`]): a command writes into a staging
//!   folder swapped in whole at the end; a folder is replaced only if softway wrote it (its
//!   [`MARKER`](super::staging::MARKER), never a familiar file name) or with `--force`; the current folder, the home
//!   folder, the folder of an input (the scenario) and any folder holding one of them are
//!   never replaced.
//! - **The as-run scenario**: the folder of a command that read a scenario holds its text as
//!   run (`scenario.toml`, with the `--set` values in its header).
//! - **Interruption**: SIGINT, SIGTERM or SIGHUP stop the work at the next step, pass,
//!   point or frequency; what was computed is written and the marker says `interrupted`
//!   (its second line, [`INTERRUPTED`](super::staging::INTERRUPTED)); the command exits
//!   130 (a second signal aborts at once).
//! - **The cost up front** ([`admit`]): time, memory and disk of the whole command (every
//!   run, pass, point and body) are estimated before anything is written; beyond the
//!   limits the command is refused unless `--yes`, beyond what can be run at all it is
//!   refused whatever the user confirms.
//!
//! A study that must survive its own process (`softway grow`: a checkpoint after every pass,
//! `--resume`) claims its folder with [`StudyFolder`] under the same rules and writes into it
//! in place, each file atomically.

use super::staging::{write_marker, StagedDir, StagingError};
use crate::build::{Estimate, Limits};
use std::path::{Path, PathBuf};

/// The output folder of a command: staged, written whole at [`JobFolder::finish`].
#[derive(Debug)]
pub struct JobFolder {
    stage: StagedDir,
}

impl JobFolder {
    /// Claims `out` for the results of `command` (`run`, `sweep`, ...: the folder rules,
    /// module docs; its marker names the command, and a folder of another command's results
    /// is not replaced without `force`); `inputs` are the files the command reads (their
    /// folders are never replaced).
    ///
    /// # Errors
    /// [`StagingError`]: a folder of the user's files or of another command's results
    /// without `force`, a protected folder, a file, a folder that cannot be made.
    pub fn begin(
        command: &str,
        out: &Path,
        force: bool,
        inputs: &[&Path],
    ) -> Result<Self, StagingError> {
        Ok(JobFolder {
            stage: StagedDir::begin_keeping(out, force, inputs, Some(command))?,
        })
    }

    /// The folder to write into (the staging folder).
    pub fn dir(&self) -> &Path {
        self.stage.path()
    }

    /// `p` (a path inside [`JobFolder::dir`]) as it will be once the folder is finished.
    pub fn final_path(&self, p: &Path) -> PathBuf {
        self.stage.final_path(p)
    }

    /// Finishes the command's folder: writes the as-run `scenario` (when the command read
    /// one and has not written it yet), marks an `interrupted` folder, and swaps the folder
    /// in. Returns `files` (paths inside [`JobFolder::dir`]) as they are once committed,
    /// the scenario's copy last.
    ///
    /// # Errors
    /// A file that cannot be written, a folder that cannot be swapped in.
    pub fn finish<R>(
        self,
        files: &[PathBuf],
        scenario: Option<&crate::scenario::Scenario<R>>,
        interrupted: bool,
    ) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
        let mut files = files.to_vec();
        if let Some(sc) = scenario {
            let copy = self.dir().join(crate::run::provenance::SCENARIO_COPY);
            if !files.contains(&copy) {
                files.push(crate::run::provenance::write_scenario_copy(sc, self.dir())?);
            }
        }
        if interrupted {
            mark_interrupted(self.dir())?;
        }
        let files = files.iter().map(|f| self.stage.final_path(f)).collect();
        self.stage.commit()?;
        Ok(files)
    }
}

/// Writes the marker of `dir` saying its results are an interrupted command's.
///
/// # Errors
/// The marker cannot be written.
pub fn mark_interrupted(dir: &Path) -> std::io::Result<()> {
    write_marker(dir, true)
}

/// The folder of a resumable study (`softway grow`), written in place.
#[derive(Debug, Clone)]
pub struct StudyFolder {
    /// The folder, as given.
    pub path: PathBuf,
}

impl StudyFolder {
    /// A new study of `command` in `out`: the folder rules of [`JobFolder::begin`], then an
    /// empty marked folder swapped in (the results of an older study there are replaced
    /// whole).
    ///
    /// # Errors
    /// As [`JobFolder::begin`].
    pub fn fresh(
        command: &str,
        out: &Path,
        force: bool,
        inputs: &[&Path],
    ) -> Result<Self, StagingError> {
        let path = StagedDir::begin_keeping(out, force, inputs, Some(command))?.commit()?;
        Ok(StudyFolder { path })
    }

    /// The study in `out` to go on with (`--resume`): it must be a folder softway wrote
    /// (its marker), not a protected one; nothing is written.
    ///
    /// # Errors
    /// [`StagingError`]: no such folder, a folder of the user's (no marker: `--resume` goes
    /// on only from softway's own), a protected folder.
    pub fn resume(out: &Path, inputs: &[&Path]) -> Result<Self, StagingError> {
        StagedDir::check_marked(out, inputs)?;
        // From here on the marker says the study is under way again.
        Ok(StudyFolder {
            path: out.to_path_buf(),
        })
    }

    /// Marks the study interrupted (its checkpoint holds the finished passes).
    ///
    /// # Errors
    /// The marker cannot be written.
    pub fn mark_interrupted(&self) -> std::io::Result<()> {
        mark_interrupted(&self.path)
    }

    /// Marks the study finished (a resumed study that ends clears the interrupted mark).
    ///
    /// # Errors
    /// The marker cannot be written.
    pub fn mark_finished(&self) -> std::io::Result<()> {
        write_marker(&self.path, false)
    }
}

/// The cost check every command makes before it writes anything: `None` when `est` may be
/// run, else the one-line reason. Beyond what can be run at all ([`Estimate::impossible`])
/// the command is refused whatever `yes` says; beyond the default [`Limits`] it is refused
/// unless `yes` (`--yes`).
pub fn admit(est: &Estimate, yes: bool) -> Option<String> {
    if let Some(why) = est.impossible() {
        return Some(why);
    }
    match est.check(&Limits::default()) {
        Some(why) if !yes => Some(why),
        _ => None,
    }
}
