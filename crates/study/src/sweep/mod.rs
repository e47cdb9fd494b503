//! Parametric studies: run every case of a sweep in parallel and resumably, and collect
//! one results table.
//!
//! [`run_study`] takes an expanded [`case::SweepPlan`] and a [`CaseRunner`] (the
//! simulation, or a stand-in in tests), writes `study.json`, `cases/<id>/…`,
//! `results.csv` and `failures.json`, and reports each finished case through a callback.

mod error;
mod from_bed;
mod rows;
mod runner;
mod simulation;
mod task;

pub use error::StudyError;
pub use from_bed::{plan_from_bed, plan_from_bed_dir};
pub use rows::{failed_row, manifest_of_plan, measured_row};
pub use runner::{
    check_study_dir, expected_cost, run_study, CaseRunner, StudyEvent, StudyOptions, StudyOutcome,
};
pub use simulation::{SimulationRunner, STOPPED};
pub use task::{
    case_states, collect_study, prepare_study, run_task, CaseState, Collected, TaskOutcome,
};
