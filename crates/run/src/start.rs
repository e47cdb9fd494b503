//! What a run starts from: its own fill (the protocol's), a bed another run saved, or a
//! packing file; and the record of that start which the run's checkpoints, its summary and
//! its `start.json` keep, so that `--resume` continues only a run that started the same way
//! (docs/user-guide.md §5).

use std::path::Path;

use case::Case;
use files::{StartKind, StartRecord};

use super::bed::{check_bed, Bed, BedError};
use crate::{read_packing, Packing, PackingError};

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

/// Why a run cannot start as asked.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// Both a bed and a packing file were given.
    #[error(
        "a bed and a packing file exclude each other: a run starts from a saved bed, from a \
         packing file, or from its own fill"
    )]
    BedAndPacking,
    /// The bed was settled under inputs that differ from the case in more than the
    /// discharge's keys.
    #[error(transparent)]
    Bed(#[from] BedError),
    /// The packing file cannot be read or does not fit the case.
    #[error(transparent)]
    Packing(#[from] PackingError),
}

impl Start {
    /// Where a run of `case` starts: from `bed` (already read, since a run without a case
    /// file takes the bed's case as its base) once it is checked against `case`, from the
    /// packing file `packing` once it is read and checked against `case`, or from the fill.
    /// The command line and the Python module both decide a run's start here.
    pub fn choose(
        case: &Case,
        bed: Option<Bed>,
        packing: Option<&Path>,
    ) -> Result<Self, StartError> {
        match (bed, packing) {
            (Some(_), Some(_)) => Err(StartError::BedAndPacking),
            (Some(bed), None) => {
                check_bed(&bed, case)?;
                Ok(Self::Bed(Box::new(bed)))
            }
            (None, Some(file)) => Ok(Self::Packing(Box::new(read_packing(file, case)?))),
            (None, None) => Ok(Self::Fill),
        }
    }

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
