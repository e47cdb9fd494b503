//! Every integration test of `study` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod study_fake;
mod tiny_hopper;

mod golden;
mod golden_silo;
mod report_build;
mod run_bed;
mod run_guard;
mod run_kinds;
mod run_mixture;
mod run_packing;
mod run_physics;
mod run_resume;
mod run_silo;
mod run_stop;
mod run_timing;
mod run_wall_forces;
mod run_wall_slip;
mod study_resume;
mod study_runner;
