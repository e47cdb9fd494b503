//! The record of what a run started from, kept by its checkpoints, its summary, its
//! `start.json` and a study's manifest, so that `--resume` continues only a run that
//! started the same way (docs/user-guide.md §5).

use std::fmt;

use serde::{Deserialize, Serialize};

/// The kind of source a run started from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StartKind {
    /// A bed saved by another run.
    Bed,
    /// A packing file.
    Packing,
}

/// The identity of what a run started from: its kind and the SHA-256 of its content (a
/// bed's body, a packing file's bytes). The path is left out, so that runs from copies of one
/// bed or file record the same start.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct StartRecord {
    /// Bed or packing.
    pub kind: StartKind,
    /// Hex SHA-256 of the content.
    pub sha256: String,
}

impl fmt::Display for StartRecord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.kind {
            StartKind::Bed => "a saved bed",
            StartKind::Packing => "a packing file",
        };
        write!(
            f,
            "{kind} (SHA-256 {})",
            &self.sha256[..self.sha256.len().min(16)]
        )
    }
}

/// "a fill" or the record in words.
pub fn describe_start(start: Option<&StartRecord>) -> String {
    start.map_or_else(|| "its own fill".to_string(), ToString::to_string)
}
