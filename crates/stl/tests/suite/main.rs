//! Every integration test of `stl` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod common;

mod ascii_errors;
mod file_errors;
mod no_panic;
mod read_valid;
mod round_trip;
mod shapes;
mod transform;
mod triangle_errors;
