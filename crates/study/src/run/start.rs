//! What a run starts from: its own fill (the protocol's), a bed another run saved, or a
//! packing file; and the record of that start which the run's checkpoints, its summary and
//! its `start.json` keep, so that `--resume` continues only a run that started the same way
//! (docs/user-guide.md §5).

use std::fmt;

use serde::{Deserialize, Serialize};

use super::bed::Bed;
use crate::hopper::Packing;

/// Name of the file in a run directory that says where a run started, when it did not fill
/// its container: the kind, the source's path and SHA-256, and for a bed the keys that
/// differ from the bed's case and the walls rebuilt for them.
pub const START_FILE: &str = "start.json";

/// What a run starts from.
#[derive(Debug, Clone, Default)]
pub enum Start {
    /// Fill the container (random insertion in batches), settle, open the gate.
    #[default]
    Fill,
    /// A bed saved by `--save-bed`: no fill and no settling; the gate opens at once.
    Bed(Box<Bed>),
    /// Particles placed at rest from a packing file, then settled; the fill is skipped.
    Packing(Box<Packing>),
}

impl Start {
    /// The record of this start, `None` for a fill.
    pub fn record(&self) -> Option<StartRecord> {
        match self {
            Self::Fill => None,
            Self::Bed(bed) => Some(StartRecord {
                kind: StartKind::Bed,
                sha256: bed.sha256().to_string(),
            }),
            Self::Packing(packing) => Some(StartRecord {
                kind: StartKind::Packing,
                sha256: packing.sha256().to_string(),
            }),
        }
    }
}

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
pub(crate) fn describe(start: Option<&StartRecord>) -> String {
    start.map_or_else(|| "its own fill".to_string(), ToString::to_string)
}
