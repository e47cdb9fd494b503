//! What a run starts from: its own fill (the protocol's), a bed another run saved, or a
//! packing file; and the record of that start which the run's checkpoints, its summary and
//! its `start.json` keep, so that `--resume` continues only a run that started the same way
//! (docs/user-guide.md §5).

use files::{StartKind, StartRecord};

use super::bed::Bed;
use crate::hopper::Packing;

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

