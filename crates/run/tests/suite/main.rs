//! Every integration test of `run` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod run_dir;
mod tiny_hopper;

mod bed;
mod calibration_tests;
mod coarse_graining;
mod fields;
mod golden;
mod golden_silo;
mod guard;
mod kinds;
mod mixture;
mod packing;
mod physics;
mod resume;
mod shapes;
mod silo;
mod stop;
mod timing;
mod unclog;
mod wall_forces;
mod wall_slip;
