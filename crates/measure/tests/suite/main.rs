//! Every integration test of `measure` in one test binary: one link instead of one per
//! file keeps the test command's build short. Each module is one file's tests.

mod bulk;
mod crossing;
mod disc_area;
mod flux;
mod pile_surfaces;
mod strip;
mod velocity_field;
