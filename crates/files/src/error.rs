//! The error type shared by every writer in `output`.

use std::path::PathBuf;

/// Why a writer could not produce its file.
///
/// Every variant names the target path so that a failed run tells the user which output to
/// look at; none of them leaves a partial file behind (see [`super::AtomicFile`]).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file system refused an operation (missing directory, permissions, full disk).
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A value could not be serialised as JSON.
    #[error("cannot serialise JSON for {path}: {source}")]
    Json {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying serialisation error.
        #[source]
        source: serde_json::Error,
    },
    /// The CSV encoder failed.
    #[error("cannot write CSV {path}: {source}")]
    Csv {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying CSV error.
        #[source]
        source: csv::Error,
    },
    /// The data handed to a writer is inconsistent (mismatched lengths, non-finite
    /// coordinates, empty ranges); the message says what to fix.
    #[error("invalid data for {path}: {reason}")]
    InvalidData {
        /// The file that was being written.
        path: PathBuf,
        /// What is wrong with the data.
        reason: String,
    },
    /// The plotting library failed to draw or encode the image.
    #[error("cannot draw {path}: {reason}")]
    Drawing {
        /// The file that was being written.
        path: PathBuf,
        /// The drawing backend's message.
        reason: String,
    },
}

impl OutputError {
    /// Builds an [`OutputError::InvalidData`] for `path`.
    pub fn invalid(path: &std::path::Path, reason: impl Into<String>) -> Self {
        Self::InvalidData {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }

    /// Builds an [`OutputError::Io`] for `path`.
    pub fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// Builds an [`OutputError::Drawing`] for `path` from any displayable backend error.
    pub(crate) fn drawing(path: &std::path::Path, error: impl std::fmt::Display) -> Self {
        Self::Drawing {
            path: path.to_path_buf(),
            reason: error.to_string(),
        }
    }

    /// Names `path` in an error raised before the target was known (rendering in memory).
    pub(crate) fn for_path(self, path: &std::path::Path) -> Self {
        match self {
            Self::InvalidData { path: old, reason } if old.as_os_str().is_empty() => {
                Self::InvalidData {
                    path: path.to_path_buf(),
                    reason,
                }
            }
            Self::Drawing { path: old, reason } if old.as_os_str().is_empty() => Self::Drawing {
                path: path.to_path_buf(),
                reason,
            },
            other => other,
        }
    }
}
