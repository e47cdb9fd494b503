//! Every integration test of `study` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod fake_study;
mod study_fake;
// The guard tests' helpers, shared with `run`'s tests (the same file, not a copy).
#[path = "../../../run/tests/suite/run_dir.rs"]
mod run_dir;

mod guard;
mod report_build;
mod report_clogging;
mod report_cohesion;
mod study_resume;
mod study_runner;
