//! Every integration test of `files` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod atomic;
mod csv_table;
mod frame;
mod plot;
mod vtu;
