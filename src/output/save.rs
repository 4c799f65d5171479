//! [`Results::save`]: the results of a run written as the command line's files, byte for
//! byte (`history.csv`, `summary.json`, `contact_nodes.csv`, `j2_rim_profile.csv`, the
//! traction files, VTU/PVD, PNG figures).

use super::files::write_json;
use super::table::Columns;
use super::vtk::{write_vtu, Field, PvdWriter};
use crate::run::error::RunError;
use crate::run::results::{Detail, FieldArray, Fields, Results};
use std::path::{Path, PathBuf};

impl Results {
    /// Writes the results into the folder `out` (created if needed) as the command line's
    /// `run` does, and returns the files written in the order the command line lists them.
    /// A table streamed to a file during the run ([`Columns::streamed_to`]) is left in place
    /// when that file is the one to write, else copied.
    ///
    /// # Errors
    /// [`RunError::Output`] naming the file.
    pub fn save(&self, out: &Path) -> Result<Vec<PathBuf>, RunError> {
        std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
        let mut files = vec![table(out, "history.csv", &self.history)?];
        match &self.detail {
            Detail::Own(w) => {
                files.extend(w.save(self, out)?);
                files.push(self.save_summary(out)?);
            }
            Detail::Panels { file, panes, size } => {
                files.extend(write_fields(out, &self.fields)?);
                files.push(self.save_summary(out)?);
                if self.plots && !panes.is_empty() {
                    let png = out.join(file);
                    crate::output::plot::panels(&png, panes, panes.len(), 1, *size)
                        .map_err(|e| RunError::output(&png, e))?;
                    files.push(png);
                }
            }
        }
        Ok(files)
    }

    /// Writes the results into the folder `out` under the rules every command keeps (the crate's
    /// `output::job`, the command line's path): written whole or not at all, a folder of the user's
    /// files refused unless `force`, the current and the home folder never replaced, the folder
    /// marked as softway's (and `interrupted` when the run was). Returns the files as
    /// [`Results::save`] lists them. What the Python package's `Result.save` calls.
    ///
    /// # Errors
    /// [`RunError::Output`]: the folder refused (the message says why and names `--force`
    /// for a folder of the user's files), a file that cannot be written.
    pub fn save_folder(&self, out: &Path, force: bool) -> Result<Vec<PathBuf>, RunError> {
        let stage = crate::output::job::JobFolder::begin("run", out, force, &[])
            .map_err(|e| RunError::output(out, e))?;
        let files = self.save(stage.dir())?;
        stage
            .finish(
                &files,
                None::<&crate::scenario::Scenario<crate::scenario::RunSpec>>,
                self.interrupted,
            )
            .map_err(|e| RunError::output(out, e))
    }

    /// `summary.json`.
    fn save_summary(&self, out: &Path) -> Result<PathBuf, RunError> {
        let sj = out.join("summary.json");
        write_json(&sj, &self.summary).map_err(|e| RunError::output(&sj, e))?;
        Ok(sj)
    }
}

/// Writes `table` as `out/name`.
pub(crate) fn table(out: &Path, name: &str, table: &Columns) -> Result<PathBuf, RunError> {
    let path = out.join(name);
    table
        .write_csv(&path)
        .map_err(|e| RunError::output(&path, e))?;
    Ok(path)
}

/// The fields as VTU files, one per frame, and `velocity.pvd` listing the frames with an
/// instant.
pub(crate) fn write_fields(out: &Path, fields: &Fields) -> Result<Vec<PathBuf>, RunError> {
    let Some(mesh) = &fields.mesh else {
        return Ok(Vec::new());
    };
    let mut files = Vec::new();
    let mut pvd = PvdWriter::new();
    for frame in &fields.frames {
        let p = out.join(&frame.file);
        write_vtu(
            &p,
            mesh,
            frame.displacement.as_deref(),
            &view(&frame.point_data),
            &view(&frame.cell_data),
        )
        .map_err(|e| RunError::output(&p, e))?;
        if let Some(t) = frame.time {
            pvd.add(t, frame.file.clone());
        }
        files.push(p);
    }
    if !pvd.is_empty() {
        let p = out.join("velocity.pvd");
        pvd.write(&p).map_err(|e| RunError::output(&p, e))?;
        files.push(p);
    }
    Ok(files)
}

/// The arrays as the VTK writer's fields.
fn view(arrays: &[FieldArray]) -> Vec<Field<'_>> {
    arrays
        .iter()
        .map(|a| Field {
            name: &a.name,
            components: a.components,
            values: &a.values,
        })
        .collect()
}

/// Claims the folder `out` for a study of `command` written in place (the Python package's
/// `sweep(out=)`: every point's folder inside it, written by the worker that ran it, then
/// the gathered table) under the rules every command keeps: a folder of the user's files,
/// or of another command's results, refused unless `force`; the current and the home folder
/// and the folders of `inputs` (the scenario) never replaced; an older study of the same
/// command there replaced whole. The folder is then empty but for its marker.
///
/// # Errors
/// [`RunError::Output`] naming the folder and why it is refused.
pub fn claim_folder(
    out: &Path,
    command: &str,
    force: bool,
    inputs: &[&Path],
) -> Result<PathBuf, RunError> {
    crate::output::job::StudyFolder::fresh(command, out, force, inputs)
        .map(|f| f.path)
        .map_err(|e| RunError::output(out, e))
}

/// Writes `files` (each a file's name and its bytes: a saved result's files, carried
/// elsewhere, as the Python package's pickled `Result` carries them) into the folder `out`
/// under the rules [`Results::save_folder`](crate::run::Results::save_folder) keeps: written whole or not at all, a folder of
/// the user's files refused unless `force`, the current and the home folder never replaced,
/// the folder marked as softway's (and `interrupted`). Returns the files' paths.
///
/// # Errors
/// [`RunError::Output`]: the folder refused (the message says why), a name that is not a
/// file's name, a file that cannot be written.
pub fn save_files(
    out: &Path,
    files: &[(String, Vec<u8>)],
    interrupted: bool,
    force: bool,
) -> Result<Vec<PathBuf>, RunError> {
    let stage = crate::output::job::JobFolder::begin("run", out, force, &[])
        .map_err(|e| RunError::output(out, e))?;
    let mut written = Vec::with_capacity(files.len());
    for (name, bytes) in files {
        let rel = Path::new(name);
        if rel.components().count() != 1 || rel.file_name().is_none() {
            return Err(RunError::Output {
                path: out.join(name),
                message: "not a file's name".into(),
            });
        }
        let p = stage.dir().join(rel);
        std::fs::write(&p, bytes).map_err(|e| RunError::output(&stage.final_path(&p), e))?;
        written.push(p);
    }
    stage
        .finish(
            &written,
            None::<&crate::scenario::Scenario<crate::scenario::RunSpec>>,
            interrupted,
        )
        .map_err(|e| RunError::output(out, e))
}
