//! The error of a job.

use std::path::{Path, PathBuf};

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
