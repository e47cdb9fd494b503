//! Calibration (`hopperflow calibrate`, docs/physics.md §12): up to two material parameters
//! searched until the runs of up to two lab tests match what the lab measured.
//!
//! Each round is a study (`rounds/round-NN/` in the output folder): the test cases at the
//! points of a small design in the current search region, each with replicates, run in
//! parallel and resumably by [`study::run_study`], or as a Slurm array. The measures read
//! from the runs' `summary.json` are fitted and inverted by [`analysis::calibration`]; the
//! next round's region follows from the estimate. `calibration.json` ([`files::CalibrationRecord`]) and `runs.csv` are
//! rewritten after every round; a calibration stopped at any point continues from its
//! finished runs, and gives the same files as one never stopped.

#![warn(missing_docs)]

mod driver;
mod error;
mod measure;
mod round;

pub use driver::{
    plan_hash, run_calibration, slurm_step, Calibration, CalibrationEvent, CalibrationOptions,
    NextRound, SlurmStep,
};
pub use error::CalibrationError;
pub use files::{
    CalibrationRecord, ParameterEstimate, RoundRecord, SurfaceRecord, TargetMatch,
    CALIBRATION_FILE, RUNS_FILE,
};
pub use measure::{has_measure, measure_value, numeric_measures};
pub use round::{round_dir, round_plan, to_physical, to_unit};
