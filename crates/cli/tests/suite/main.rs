//! Every integration test of `cli` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

#[path = "../../../case/tests/suite/bad_case_files.rs"]
mod bad_case_files;
mod run_cli;
mod tiny;

mod bad_input;
mod bed_and_packing;
mod bench_silo_inputs;
mod calibrate_cli;
mod calibration_loop;
mod doc_paths;
mod exit_codes;
mod quick_study;
mod real_kill;
mod slurm_input;
mod study_from_bed;
