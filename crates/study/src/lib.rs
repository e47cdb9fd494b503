//! Studies: many cases of a sweep run to one results table, locally (in parallel, resumably)
//! or as a Slurm job array.
//!
//! - [`run_study`] runs every case of an expanded [`case::SweepPlan`] through a
//!   [`CaseRunner`] (the simulation, [`SimulationRunner`], or a stand-in in tests) and keeps
//!   `study.json`, `cases/<id>/…`, `results.csv` and `failures.json` up to date;
//! - [`prepare_study`], [`run_task`] and [`collect_study`] are the same study cut into the
//!   tasks of a Slurm array; [`array_script`] and [`report_script`] write its job scripts.

#![warn(missing_docs)]

mod cluster;
mod sweep;

pub use cluster::{
    array_script, case_statuses, job_name, known_partitions, on_path, queued_cases, report_script,
    sbatch, shell_quote, write_jobs, CaseStanding, Jobs, JobsError, SlurmOptions, Submission,
    TimeLimit, SUBMISSIONS_FILE, TIME_FORMATS,
};
pub use sweep::{
    case_states, check_study_dir, collect_study, expected_cost, failed_row, manifest_of_plan,
    measured_row, plan_from_bed, plan_from_bed_dir, prepare_study, run_study, run_task, CaseRunner,
    CaseState, Collected, SimulationRunner, StudyError, StudyEvent, StudyOptions, StudyOutcome,
    TaskOutcome, STOPPED,
};
