//! The error of a scenario: the file, the key at fault and what is allowed.

use std::path::PathBuf;

/// A scenario error: the file, the key at fault and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file cannot be read.
    #[error("{path}: cannot read the scenario: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error (unknown key, wrong type).
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A value out of its allowed range.
    #[error("{path}: `{key}` = {value}: {allowed}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Dotted key, e.g. `bar.length` or `runs[2].h`.
        key: String,
        /// The value found.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A required key is missing.
    #[error("{path}: missing `{key}`: {why}")]
    Missing {
        /// The file.
        path: PathBuf,
        /// Dotted key.
        key: String,
        /// What it is for.
        why: String,
    },
}
