//! Why a study's own files (`study.json`, `results.csv`) could not be read or written.

use std::path::PathBuf;

use crate::error::OutputError;

/// Why a study's manifest or results table could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum StudyFileError {
    /// The file could not be opened or read.
    #[error("cannot access {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The file was read but does not hold what it should.
    #[error("cannot read {path}: {reason}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

impl StudyFileError {
    /// The error of an input/output operation on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
