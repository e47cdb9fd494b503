//! Every integration test of `case` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod bad_case_files;
mod bad_cases;
mod calibration_file;
mod case_file;
mod coarse_graining;
mod cohesion;
mod fuzz;
mod kinds;
mod materials;
mod shapes;
mod shipped;
mod sweep;
