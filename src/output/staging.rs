//! Output folders written whole or not at all.
//!
//! A command never writes into its output folder directly: it writes into a fresh staging
//! folder beside it (`.softway-tmp-<pid>-<n>`: a short name, so that an output folder may
//! have any name the filesystem allows, up to [`NAME_MAX`] bytes), and [`StagedDir::commit`]
//! swaps it in at the end (the older folder, if any, is renamed aside, as
//! `.softway-old-<pid>-<n>`, and removed). So an output
//! folder never mixes the files of an older run with those of a newer one, a failed run
//! leaves the older results as they were, and a killed process leaves at most a folder
//! under a temporary name (removed by the next command writing beside it).
//!
//! Every folder written this way holds a marker file [`MARKER`]. An existing folder is
//! replaced only if it holds the marker (or is empty): a folder of other files is refused
//! unless the caller passes `force` (the command line's `--force`), so that a mistyped
//! `--out` cannot wipe a folder of the user's own.
//!
//! Some folders are never replaced, `force` or not ([`StagingError::Protected`]): the
//! current folder, the home folder (`$HOME`), the folder of an input (the scenario file) and
//! any folder holding one of them, however the path is written (absolute, relative, with
//! `..`, through symbolic links: the paths are compared canonicalized).
//!
//! A target that is a symbolic link to a folder is written through: the folder it points to
//! is the one replaced (by the same rules) and the link is kept, so the link shows the new
//! results and no older results are left where it pointed. A link to nothing is refused.
//!
//! The staging folder is an implementation detail: [`public_message`] rewrites a message
//! that names it (an error of a file written into it) to name the output folder instead,
//! and every path in a message is shown with its control characters escaped.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The marker file of a folder written by softway (holds the version that wrote it).
pub const MARKER: &str = ".softway";

/// The marker's second line when the folder holds an interrupted command's results.
pub const INTERRUPTED: &str = "interrupted";

/// The marker's line naming the command that wrote the folder (`command: sweep`).
const COMMAND: &str = "command: ";

/// Writes the [`MARKER`] of the folder `dir` (atomically): the version that wrote it,
/// [`INTERRUPTED`] on a second line when its results are an interrupted command's, and the
/// command that wrote it (`command: run`) when the marker there names one (a marker
/// rewritten keeps its command). The one writer of the marker, for a staged folder and a
/// study written in place alike.
///
/// # Errors
/// The marker cannot be written.
pub fn write_marker(dir: &Path, interrupted: bool) -> std::io::Result<()> {
    write_marker_as(dir, marker_command(dir).as_deref(), interrupted)
}

/// As [`write_marker`], naming `command` (the study a folder holds: `run`, `sweep`, ...).
///
/// # Errors
/// The marker cannot be written.
pub fn write_marker_as(
    dir: &Path,
    command: Option<&str>,
    interrupted: bool,
) -> std::io::Result<()> {
    let mut text = format!("softway {}\n", env!("CARGO_PKG_VERSION"));
    if interrupted {
        text.push_str(INTERRUPTED);
        text.push('\n');
    }
    if let Some(c) = command {
        text.push_str(COMMAND);
        text.push_str(c);
        text.push('\n');
    }
    crate::output::files::write_atomic(&dir.join(MARKER), text.as_bytes())
}

/// The command the [`MARKER`] of `dir` names, if it is there and names one (markers of
/// older versions name none).
pub fn marker_command(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    text.lines()
        .find_map(|l| l.strip_prefix(COMMAND))
        .map(str::to_string)
}

/// The longest name of a file or folder, bytes (`NAME_MAX` of Linux's filesystems, macOS's
/// and Windows' 255 characters).
pub const NAME_MAX: usize = 255;

/// `path` as a message shows it: control characters (a NUL, a newline) escaped, so that an
/// error stays one line and shows what was given.
pub fn shown(path: &Path) -> String {
    escape_controls(&path.to_string_lossy())
}

/// `text` with its control characters escaped (`\0`, `\n`, `\u{1b}`).
pub fn escape_controls(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_debug().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The staging folders made by this process and their output folders (kept after the
/// staging folder is gone: an error is printed after the stage is dropped).
static STAGED: std::sync::Mutex<Vec<(String, String)>> = std::sync::Mutex::new(Vec::new());

/// `message` with every staging folder of this process it names replaced by its output
/// folder (a user knows the folder they asked for; the staging folder is removed by the
/// time the message is read).
pub fn public_message(message: &str) -> String {
    let staged = STAGED.lock().map(|v| v.clone()).unwrap_or_default();
    let mut m = message.to_string();
    for (staging, target) in staged.iter().rev() {
        m = m.replace(staging.as_str(), target);
    }
    m
}

/// Why an output folder cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum StagingError {
    /// The target exists and is not a folder.
    #[error("--out {}: is a file, not a folder; give a folder to write into", shown(.0))]
    NotAFolder(PathBuf),
    /// The target holds files that softway did not write.
    #[error(
        "--out {}: the folder exists and holds files not written by softway; \
         give another --out, or --force to replace the folder and everything in it",
        shown(.0)
    )]
    Foreign(PathBuf),
    /// The target holds the results of another command (its marker says which).
    #[error(
        "--out {}: the folder holds the results of `softway {wrote}`, not of `softway {this}`; \
         give another --out, or --force to replace them",
        shown(.path)
    )]
    OtherCommand {
        /// The output folder asked for.
        path: PathBuf,
        /// The command whose results it holds.
        wrote: String,
        /// The command asking for it.
        this: String,
    },
    /// The target is, or holds, a folder never replaced (module docs).
    #[error(
        "--out {}: the folder is or holds {what} ({}); softway never replaces the current folder, \
         the home folder, the scenario's folder or a folder holding one of them, even with \
         --force: give a new folder",
        shown(.path), shown(.holds)
    )]
    Protected {
        /// The output folder asked for.
        path: PathBuf,
        /// What it holds: `the current folder`, ...
        what: &'static str,
        /// That folder.
        holds: PathBuf,
    },
    /// The target is a symbolic link to nothing.
    #[error(
        "--out {}: is a symbolic link to {}, which does not exist; create that folder, or \
         give another --out",
        shown(.0), shown(.1)
    )]
    DanglingLink(PathBuf, PathBuf),
    /// A folder cannot be created, read, renamed or removed.
    #[error("--out {}: {what}: {source}", shown(.path))]
    Io {
        /// The output folder asked for.
        path: PathBuf,
        /// What was being done.
        what: String,
        /// The cause.
        source: std::io::Error,
    },
}

/// A staging folder for an output folder; removed on drop unless committed.
#[derive(Debug)]
pub struct StagedDir {
    /// The output folder as given (messages, [`StagedDir::final_path`]).
    target: PathBuf,
    /// The folder replaced at the commit: `target` canonicalized (through a symbolic link).
    real: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// [`StagedDir::begin_keeping`] with no input to keep.
    #[cfg(test)]
    ///
    /// # Errors
    /// As [`StagedDir::begin_keeping`].
    pub fn begin(target: &Path, force: bool) -> Result<Self, StagingError> {
        Self::begin_keeping(target, force, &[], None)
    }

    /// Checks `target` and creates a fresh staging folder beside it (its parent folders
    /// are created as needed), with the [`MARKER`] file. Stale staging folders of dead
    /// processes beside `target` are removed. `target` must not be, nor hold, the current
    /// folder, the home folder or the folder of one of `inputs` (module docs). `command`
    /// (the study the folder will hold: `run`, `sweep`, ...) is written in the marker, and a
    /// folder whose marker names another command is not replaced without `force` (a scenario
    /// named `wheel-sweep` run by `softway run` and `wheel` swept by `softway sweep` would
    /// both write `out/wheel-sweep/`).
    ///
    /// # Errors
    /// [`StagingError::NotAFolder`], [`StagingError::Protected`],
    /// [`StagingError::DanglingLink`], [`StagingError::Foreign`] and
    /// [`StagingError::OtherCommand`] (unless `force`), [`StagingError::Io`] when the
    /// folders cannot be created.
    pub fn begin_keeping(
        target: &Path,
        force: bool,
        inputs: &[&Path],
        command: Option<&str>,
    ) -> Result<Self, StagingError> {
        let io = |what: &str, source: std::io::Error| StagingError::Io {
            path: target.to_path_buf(),
            what: what.to_string(),
            source,
        };
        // The last component as written: `Path::file_name` skips a trailing `.` (`out/.`
        // would name `out`, the folder of every result).
        let written = target.to_string_lossy();
        let last = written
            .trim_end_matches('/')
            .rsplit('/')
            .next()
            .unwrap_or("");
        let name = target
            .file_name()
            .filter(|n| !n.is_empty() && *n != "." && *n != "..")
            .filter(|_| last != "." && last != "..")
            .ok_or_else(|| {
                io(
                    "not a folder name",
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidInput,
                        "give a folder path that ends in a name",
                    ),
                )
            })?
            .to_string_lossy()
            .into_owned();
        if name.len() > NAME_MAX {
            return Err(io(
                &format!(
                    "its name is {} bytes, more than the {NAME_MAX} a folder's name may have",
                    name.len()
                ),
                std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "give a shorter --out (or a shorter `name` in the scenario)",
                ),
            ));
        }
        // The folder that would be replaced, canonical, checked (None: nothing there yet).
        let check = |path: &Path| -> Result<Option<PathBuf>, StagingError> {
            let Ok(link) = std::fs::symlink_metadata(path) else {
                return Ok(None);
            };
            let real = match std::fs::metadata(path) {
                Err(_) if link.file_type().is_symlink() => {
                    let to = std::fs::read_link(path).unwrap_or_default();
                    return Err(StagingError::DanglingLink(target.to_path_buf(), to));
                }
                Err(e) => return Err(io("cannot read it", e)),
                Ok(m) if !m.is_dir() => return Err(StagingError::NotAFolder(target.to_path_buf())),
                Ok(_) => std::fs::canonicalize(path).map_err(|e| io("cannot read it", e))?,
            };
            refuse_protected(target, &real, inputs)?;
            if !force && !replaceable(&real).map_err(|e| io("cannot read it", e))? {
                return Err(StagingError::Foreign(target.to_path_buf()));
            }
            if let (false, Some(this), Some(wrote)) = (force, command, marker_command(&real)) {
                if wrote != this {
                    return Err(StagingError::OtherCommand {
                        path: target.to_path_buf(),
                        wrote,
                        this: this.to_string(),
                    });
                }
            }
            Ok(Some(real))
        };
        let existing = check(target)?;
        if existing.is_none() {
            // A path through a folder that does not exist (`new/../study`) names an existing
            // one once its parents are made: checked before anything is made.
            check(&lexical(target))?;
        }
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(|e| {
            // Name the ancestor that is in the way when it is a file (e.g. /dev/null/x).
            match parent
                .ancestors()
                .find(|a| a.exists())
                .filter(|a| !a.is_dir())
            {
                Some(a) => io(
                    &format!(
                        "cannot create its parent folder: {} is not a folder",
                        a.display()
                    ),
                    e,
                ),
                None => io("cannot create its parent folder", e),
            }
        })?;
        // Where the folder is: through every symbolic link (of the target or its parents).
        let real = match existing {
            Some(real) => real,
            None => {
                let real = std::fs::canonicalize(&parent)
                    .map_err(|e| io("cannot read its parent folder", e))?
                    .join(&name);
                // Once the parents are made (links among them), checked again.
                check(&real)?.unwrap_or(real)
            }
        };
        let (parent, name) = match (real.parent(), real.file_name()) {
            (Some(p), Some(n)) => (p.to_path_buf(), n.to_string_lossy().into_owned()),
            _ => (parent, name),
        };
        remove_stale(&parent, &name);
        static SERIAL: AtomicU64 = AtomicU64::new(0);
        let staging = parent.join(format!(
            ".softway-tmp-{}-{}",
            std::process::id(),
            SERIAL.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir(&staging).map_err(|e| io("cannot create a folder beside it", e))?;
        if let Ok(mut v) = STAGED.lock() {
            v.push((
                staging.to_string_lossy().into_owned(),
                target.to_string_lossy().into_owned(),
            ));
        }
        let dir = StagedDir {
            target: target.to_path_buf(),
            real,
            staging,
            committed: false,
        };
        write_marker_as(&dir.staging, command, false)
            .map_err(|e| io("cannot write into a folder beside it", e))?;
        Ok(dir)
    }

    /// Checks that `target` is a folder softway wrote (it holds the [`MARKER`]) and is
    /// neither, nor holds, a protected folder (module docs; `inputs` as in
    /// [`StagedDir::begin_keeping`]): a folder to go on writing into in place (a resumed
    /// study). Nothing is written.
    ///
    /// # Errors
    /// [`StagingError::Io`] when it does not exist, [`StagingError::NotAFolder`],
    /// [`StagingError::Protected`], [`StagingError::Foreign`] without the marker.
    pub fn check_marked(target: &Path, inputs: &[&Path]) -> Result<(), StagingError> {
        let io = |what: &str, source: std::io::Error| StagingError::Io {
            path: target.to_path_buf(),
            what: what.to_string(),
            source,
        };
        let meta = std::fs::metadata(target).map_err(|e| io("cannot read it", e))?;
        if !meta.is_dir() {
            return Err(StagingError::NotAFolder(target.to_path_buf()));
        }
        let real = std::fs::canonicalize(target).map_err(|e| io("cannot read it", e))?;
        refuse_protected(target, &real, inputs)?;
        if !real.join(MARKER).is_file() {
            return Err(StagingError::Foreign(target.to_path_buf()));
        }
        Ok(())
    }

    /// The folder to write into.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// `p` (a path inside the staging folder) as it will be once committed.
    pub fn final_path(&self, p: &Path) -> PathBuf {
        p.strip_prefix(&self.staging)
            .map(|rel| self.target.join(rel))
            .unwrap_or_else(|_| p.to_path_buf())
    }

    /// Swaps the staging folder in as the output folder: the older folder, if any, is
    /// renamed aside, the staging folder renamed into place, the older one removed.
    ///
    /// # Errors
    /// [`StagingError::Io`] when a rename fails (the older folder is then put back).
    pub fn commit(mut self) -> Result<PathBuf, StagingError> {
        let io = |what: &str, source: std::io::Error| StagingError::Io {
            path: self.target.clone(),
            what: what.to_string(),
            source,
        };
        let aside = self.staging.with_file_name(
            self.staging
                .file_name()
                .map(|n| {
                    n.to_string_lossy()
                        .replace(".softway-tmp-", ".softway-old-")
                })
                .unwrap_or_default(),
        );
        let had_old = match std::fs::symlink_metadata(&self.real) {
            Ok(_) => {
                std::fs::rename(&self.real, &aside)
                    .map_err(|e| io("cannot move the older results aside", e))?;
                true
            }
            Err(_) => false,
        };
        if let Err(e) = std::fs::rename(&self.staging, &self.real) {
            if had_old {
                let _ = std::fs::rename(&aside, &self.real);
            }
            return Err(io("cannot move the new results into place", e));
        }
        self.committed = true;
        if had_old {
            let _ = std::fs::remove_dir_all(&aside);
        }
        Ok(self.target.clone())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// `path` from its deepest existing ancestor (canonicalized) on, its `.` and `..` resolved
/// as written: the folder it names once its missing parents are made.
fn lexical(path: &Path) -> PathBuf {
    let absolute = std::env::current_dir()
        .map(|d| d.join(path))
        .unwrap_or_else(|_| path.to_path_buf());
    let base = absolute
        .ancestors()
        .find(|a| a.exists())
        .unwrap_or(Path::new("/"));
    let mut out = std::fs::canonicalize(base).unwrap_or_else(|_| base.to_path_buf());
    let rest = absolute.strip_prefix(base).unwrap_or(Path::new(""));
    for c in rest.components() {
        match c {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::Normal(n) => out.push(n),
            _ => {}
        }
    }
    out
}

/// [`StagingError::Protected`] when the folder `real` (canonical; `target` as given) is, or
/// holds, one of the folders never replaced ([`protected`]).
fn refuse_protected(target: &Path, real: &Path, inputs: &[&Path]) -> Result<(), StagingError> {
    match protected(inputs)
        .into_iter()
        .find(|(_, p)| p.starts_with(real))
    {
        Some((what, holds)) => Err(StagingError::Protected {
            path: target.to_path_buf(),
            what,
            holds,
        }),
        None => Ok(()),
    }
}

/// The folders never replaced, canonical, with what they are: the current folder, the
/// home folder and the folders of `inputs` (those that exist).
fn protected(inputs: &[&Path]) -> Vec<(&'static str, PathBuf)> {
    let mut v = Vec::new();
    if let Ok(d) = std::env::current_dir().and_then(std::fs::canonicalize) {
        v.push(("the current folder", d));
    }
    if let Some(h) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        if let Ok(h) = std::fs::canonicalize(h) {
            v.push(("the home folder", h));
        }
    }
    for input in inputs {
        if let Ok(p) = std::fs::canonicalize(input) {
            let folder = if p.is_dir() {
                p
            } else {
                p.parent().map(Path::to_path_buf).unwrap_or(p)
            };
            v.push(("the scenario's folder", folder));
        }
    }
    v
}

/// True when `dir` may be replaced without `--force`: empty, or written by softway (it
/// holds the [`MARKER`]; a file with a familiar name, `summary.json` or `sweep.csv`, does
/// not make a folder softway's: it may be a copy the user keeps among their own files).
fn replaceable(dir: &Path) -> std::io::Result<bool> {
    let mut empty = true;
    for entry in std::fs::read_dir(dir)? {
        let name = entry?.file_name();
        if name == MARKER {
            return Ok(true);
        }
        empty = false;
    }
    Ok(empty)
}

/// Removes staging and set-aside folders in `parent` left by processes that no longer run
/// (killed, e.g. by SIGKILL): `.softway-tmp-<pid>-<n>`, `.softway-old-<pid>-<n>`, and those
/// of `name` as older versions named them (`.<name>.softway-tmp-<pid>-<n>`). Only where
/// `/proc` tells which processes run.
fn remove_stale(parent: &Path, name: &str) {
    let proc = Path::new("/proc/self");
    if !proc.exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let rest = [".softway-tmp-", ".softway-old-"].iter().find_map(|k| {
            file.strip_prefix(*k)
                .or_else(|| file.strip_prefix(&format!(".{name}{k}")))
        });
        let Some(pid) = rest.and_then(|r| r.split('-').next()?.parse::<u32>().ok()) else {
            continue;
        };
        if pid != std::process::id() && !Path::new("/proc").join(pid.to_string()).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("softway-staging-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_commit_replaces_the_older_results_whole() {
        let d = tmp("swap");
        let out = d.join("out");
        let s = StagedDir::begin(&out, false).unwrap();
        std::fs::write(s.path().join("old.txt"), "old").unwrap();
        s.commit().unwrap();
        assert_eq!(entries(&out), [MARKER, "old.txt"]);
        let s = StagedDir::begin(&out, false).unwrap();
        std::fs::write(s.path().join("new.txt"), "new").unwrap();
        // Nothing visible before the commit.
        assert_eq!(entries(&out), [MARKER, "old.txt"]);
        assert_eq!(s.final_path(&s.path().join("new.txt")), out.join("new.txt"));
        s.commit().unwrap();
        assert_eq!(entries(&out), [MARKER, "new.txt"]);
        assert_eq!(entries(&d), ["out"]);
    }

    /// A scenario named `wheel-sweep` run by `softway run` and `wheel` swept by `softway
    /// sweep` both default to `out/wheel-sweep/`: the marker names the command, and the one
    /// does not replace the other's results without `force`; the same command replaces its
    /// own, a marker of an older version (no command) is replaced by any, an interrupted
    /// mark rewritten keeps the command.
    #[test]
    fn a_folder_of_another_commands_results_is_not_replaced_without_force() {
        let d = tmp("command");
        let out = d.join("wheel-sweep");
        StagedDir::begin_keeping(&out, false, &[], Some("run"))
            .unwrap()
            .commit()
            .unwrap();
        assert_eq!(marker_command(&out).as_deref(), Some("run"));
        let e = StagedDir::begin_keeping(&out, false, &[], Some("sweep")).unwrap_err();
        assert!(matches!(e, StagingError::OtherCommand { .. }), "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains("`softway run`") && msg.contains("--force"),
            "{msg}"
        );
        StagedDir::begin_keeping(&out, false, &[], Some("run"))
            .unwrap()
            .commit()
            .unwrap();
        write_marker(&out, true).unwrap();
        let text = std::fs::read_to_string(out.join(MARKER)).unwrap();
        assert!(text.lines().any(|l| l == INTERRUPTED), "{text}");
        assert_eq!(marker_command(&out).as_deref(), Some("run"));
        StagedDir::begin_keeping(&out, true, &[], Some("sweep"))
            .unwrap()
            .commit()
            .unwrap();
        assert_eq!(marker_command(&out).as_deref(), Some("sweep"));
        std::fs::write(out.join(MARKER), "softway 0.1.0\n").unwrap();
        StagedDir::begin_keeping(&out, false, &[], Some("run"))
            .unwrap()
            .commit()
            .unwrap();
        assert_eq!(marker_command(&out).as_deref(), Some("run"));
    }

    #[test]
    fn a_dropped_stage_leaves_nothing_and_the_older_results_stand() {
        let d = tmp("drop");
        let out = d.join("out");
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join(MARKER), "softway\n").unwrap();
        std::fs::write(out.join("summary.json"), "{}").unwrap();
        {
            let s = StagedDir::begin(&out, false).unwrap();
            std::fs::write(s.path().join("half.csv"), "1,2").unwrap();
        }
        assert_eq!(entries(&d), ["out"]);
        assert_eq!(entries(&out), [MARKER, "summary.json"]);
    }

    /// A folder is softway's only by its marker: files with the names softway writes
    /// (`summary.json`, `sweep.csv`, a subfolder of points) do not make it replaceable.
    #[test]
    fn familiar_names_without_the_marker_are_the_users() {
        let d = tmp("familiar");
        for name in [
            "summary.json",
            "sweep.csv",
            "compare.csv",
            "converge.csv",
            "modes.pvd",
        ] {
            let out = d.join(name.replace('.', "-"));
            std::fs::create_dir_all(out.join("sub")).unwrap();
            std::fs::write(out.join(name), "mine").unwrap();
            std::fs::write(out.join("sub").join("notes.txt"), "mine").unwrap();
            let e = StagedDir::begin(&out, false).unwrap_err();
            assert!(matches!(e, StagingError::Foreign(_)), "{name}: {e}");
            assert_eq!(std::fs::read_to_string(out.join(name)).unwrap(), "mine");
            let mut want = vec![name.to_string(), "sub".to_string()];
            want.sort();
            assert_eq!(entries(&out), want);
        }
    }

    #[test]
    fn a_foreign_folder_or_a_file_is_refused() {
        let d = tmp("foreign");
        let out = d.join("mine");
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join("thesis.tex"), "x").unwrap();
        let e = StagedDir::begin(&out, false).unwrap_err();
        assert!(matches!(e, StagingError::Foreign(_)), "{e}");
        assert!(e.to_string().contains("--force"), "{e}");
        assert_eq!(entries(&d), ["mine"]);
        // With force it is replaced.
        StagedDir::begin(&out, true).unwrap().commit().unwrap();
        assert_eq!(entries(&out), [MARKER]);
        let f = d.join("file");
        std::fs::write(&f, "x").unwrap();
        let e = StagedDir::begin(&f, true).unwrap_err();
        assert!(matches!(e, StagingError::NotAFolder(_)), "{e}");
    }

    /// A folder holding an input, the current folder or the home folder is never replaced,
    /// `force` or not, however written; nothing is created or removed.
    #[test]
    fn a_folder_holding_an_input_is_never_replaced() {
        let d = tmp("protected");
        let inner = d.join("work").join("study");
        std::fs::create_dir_all(&inner).unwrap();
        let scenario = inner.join("s.toml");
        std::fs::write(&scenario, "kind = \"sdof\"").unwrap();
        for target in [
            inner.clone(),
            d.join("work"),
            inner.join("..").join("study"),
            d.join("work").join(".").join("study"),
        ] {
            for force in [false, true] {
                let e = StagedDir::begin_keeping(&target, force, &[&scenario], None).unwrap_err();
                assert!(matches!(e, StagingError::Protected { .. }), "{e}");
                assert!(e.to_string().contains("the scenario's folder"), "{e}");
            }
        }
        assert_eq!(entries(&inner), ["s.toml"]);
        assert_eq!(entries(&d.join("work")), ["study"]);
        let cwd = std::env::current_dir().unwrap();
        let e = StagedDir::begin(&cwd, true).unwrap_err();
        assert!(e.to_string().contains("the current folder"), "{e}");
        // Through a folder that does not exist yet: the path names `study` once made.
        let through = d.join("work").join("new").join("..").join("study");
        let e = StagedDir::begin_keeping(&through, true, &[&scenario], None).unwrap_err();
        assert!(e.to_string().contains("the scenario's folder"), "{e}");
        assert_eq!(entries(&inner), ["s.toml"]);
        // `work/.` is `work` to Path::file_name: refused as no folder name.
        for dot in [d.join("work").join("."), d.join("work").join("./")] {
            let e = StagedDir::begin(&dot, true).unwrap_err();
            assert!(e.to_string().contains("not a folder name"), "{e}");
        }
        // A folder beside the input is fine.
        StagedDir::begin_keeping(&d.join("work").join("out"), false, &[&scenario], None)
            .unwrap()
            .commit()
            .unwrap();
    }

    /// A symbolic link to a softway folder is written through: the folder it points to is
    /// replaced, the link kept. A link to nothing is refused.
    #[cfg(unix)]
    #[test]
    fn a_link_to_an_output_folder_is_written_through() {
        let d = tmp("link");
        let results = d.join("results");
        let s = StagedDir::begin(&results, false).unwrap();
        std::fs::write(s.path().join("old.txt"), "old").unwrap();
        s.commit().unwrap();
        let link = d.join("latest");
        std::os::unix::fs::symlink(&results, &link).unwrap();
        let s = StagedDir::begin(&link, false).unwrap();
        std::fs::write(s.path().join("new.txt"), "new").unwrap();
        assert_eq!(
            s.final_path(&s.path().join("new.txt")),
            link.join("new.txt")
        );
        s.commit().unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(entries(&results), [MARKER, "new.txt"]);
        assert_eq!(entries(&d), ["latest", "results"]);
        let dangling = d.join("dangling");
        std::os::unix::fs::symlink(d.join("nothing"), &dangling).unwrap();
        let e = StagedDir::begin(&dangling, true).unwrap_err();
        assert!(matches!(e, StagingError::DanglingLink(..)), "{e}");
        assert!(!d.join("nothing").exists());
    }

    #[test]
    fn stale_folders_of_dead_processes_are_removed() {
        let d = tmp("stale");
        // No process has pid 4294967295 (above pid_max): its folders, named as now and as
        // older versions named them, are removed; a live process's (this one's) are kept.
        let stale = [
            d.join(".softway-tmp-4294967295-0"),
            d.join(".softway-old-4294967295-3"),
            d.join(".out.softway-tmp-4294967295-0"),
        ];
        let live = d.join(format!(".softway-tmp-{}-999999", std::process::id()));
        for f in stale.iter().chain([&live]) {
            std::fs::create_dir_all(f).unwrap();
        }
        let s = StagedDir::begin(&d.join("out"), false).unwrap();
        if Path::new("/proc/self").exists() {
            assert!(stale.iter().all(|f| !f.exists()));
        }
        assert!(live.exists());
        s.commit().unwrap();
    }

    #[test]
    fn a_name_of_255_bytes_is_staged_and_one_longer_refused() {
        let d = tmp("long");
        let ok = d.join("n".repeat(NAME_MAX));
        let s = StagedDir::begin(&ok, false).unwrap();
        // The staging folder's name is short whatever the target's.
        let staged = s.path().file_name().unwrap().len();
        assert!(staged < 40, "{}", s.path().display());
        std::fs::write(s.path().join("a.txt"), "a").unwrap();
        s.commit().unwrap();
        assert!(ok.join("a.txt").is_file());
        let e = StagedDir::begin(&d.join("n".repeat(NAME_MAX + 1)), false).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("256 bytes") && m.contains("255"), "{m}");
        assert_eq!(entries(&d), ["n".repeat(NAME_MAX)]);
    }

    #[test]
    fn messages_name_the_output_folder_not_the_staging_folder() {
        let d = tmp("public");
        let out = d.join("results");
        let s = StagedDir::begin(&out, false).unwrap();
        let inside = s.path().join("history.csv");
        let m = format!("cannot write {}: disk full", inside.display());
        drop(s);
        assert_eq!(
            public_message(&m),
            format!(
                "cannot write {}: disk full",
                out.join("history.csv").display()
            )
        );
        // Control characters in a path are shown escaped, on one line.
        let e = StagingError::NotAFolder(PathBuf::from("a\nb\0c"));
        assert_eq!(
            e.to_string(),
            "--out a\\nb\\0c: is a file, not a folder; give a folder to write into"
        );
    }
}
