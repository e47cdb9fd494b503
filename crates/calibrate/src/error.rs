//! Why a calibration could not go on.

use std::path::PathBuf;

use thiserror::Error;

/// A calibration's failure, with what to do about it.
#[derive(Debug, Error)]
pub enum CalibrationError {
    /// A round's study failed as a whole (its folder, its files).
    #[error("round {round}: {source}")]
    Study {
        /// Round number (from 1).
        round: u32,
        /// The study's error.
        #[source]
        source: Box<study::StudyError>,
    },
    /// A test case could not be set up at a design point.
    #[error("round {round}: the test case cannot run at a design point:\n{source}")]
    Case {
        /// Round number.
        round: u32,
        /// The case's errors.
        #[source]
        source: case::ConfigErrors,
    },
    /// A run finished without the measure a target names.
    #[error(
        "{run}: its summary.json has no number `{measure}`; the numbers it has are: {available}"
    )]
    MissingMeasure {
        /// The run's summary file.
        run: PathBuf,
        /// The target's measure.
        measure: String,
        /// The numeric fields the summary has, comma-separated.
        available: String,
    },
    /// Too few runs of a round gave a measure to fit its surface.
    #[error("round {round}: {reason}")]
    Fit {
        /// Round number.
        round: u32,
        /// What the fit lacked.
        reason: String,
    },
    /// The output folder holds another calibration.
    #[error(
        "{dir} holds a calibration of other inputs (its plan hash {found}, this one's {expected}): \
         choose another --out, or remove the folder to start again"
    )]
    DifferentCalibration {
        /// The output folder.
        dir: PathBuf,
        /// Hash recorded there.
        found: String,
        /// Hash of this calibration.
        expected: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Stopped by a signal: the running cases checkpointed; the same command continues.
    #[error(
        "stopped by a signal: running cases wrote checkpoints; rerun the same command to continue"
    )]
    Stopped,
}
