//! Every integration test of `dem` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod common;

mod checkpoint;
mod clumps;
mod cohesion;
mod determinism;
mod energy;
mod errors;
mod golden;
mod golden_silo;
mod material_table;
mod moving_walls;
mod rebuilds;
mod region_force;
mod removal;
mod replace_wall;
mod watch;
