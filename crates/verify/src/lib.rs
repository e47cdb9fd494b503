//! Verification suite of the DEM engine: the single-impact benchmarks of Chung & Ooi (2011),
//! Thornton's normalised oblique impacts, Hertz impacts of unequal and of dissimilar spheres
//! (H1), the analytic sliding/rolling cases, the walls of any shape (W1–W6), the cohesion
//! laws (J1–J4) and rigid clumps (RB1–RB4) of docs/physics.md §9, each reported as rows of
//! expected and measured values.
//!
//! Every case lives in its own file whose module documentation gives the set-up, the
//! expected values and their source, and the tolerance with its reason.

pub mod a1;
pub mod a2;
pub mod a3;
pub mod a4;
mod adhesion;
pub mod co1;
pub mod co2;
pub mod co3;
pub mod co4;
pub mod co5;
pub mod cot;
mod error;
pub mod h1;
pub mod impact;
pub mod j1;
pub mod j2;
pub mod j3;
pub mod j4;
mod meshes;
pub mod p1;
pub mod profile;
pub mod rb1;
pub mod rb2;
pub mod rb3;
pub mod rb4;
mod resolution;
mod row;
mod surface;
pub mod w1;
pub mod w2;
pub mod w3;
pub mod w4;
pub mod w5;
pub mod w6;

pub use error::VerifyError;
pub use resolution::Resolution;
pub use row::Row;

use rayon::prelude::*;

/// One verification case: its name and the function that runs it.
type Case = (
    &'static str,
    fn(Resolution) -> Result<Vec<Row>, VerifyError>,
);

/// Every case of docs/physics.md §9 that this crate implements, in the order of the spec.
const CASES: [Case; 26] = [
    ("CO1", co1::run),
    ("CO2", co2::run),
    ("CO3", co3::run),
    ("CO4", co4::run),
    ("CO5", co5::run),
    ("CO-T", cot::run),
    ("P1", p1::run),
    ("H1", h1::run),
    ("A1", a1::run),
    ("A2", a2::run),
    ("A3", a3::run),
    ("A4", a4::run),
    ("W1", w1::run),
    ("W2", w2::run),
    ("W3", w3::run),
    ("W4", w4::run),
    ("W5", w5::run),
    ("W6", w6::run),
    ("J1", j1::run),
    ("J2", j2::run),
    ("J3", j3::run),
    ("J4", j4::run),
    ("RB1", rb1::run),
    ("RB2", rb2::run),
    ("RB3", rb3::run),
    ("RB4", rb4::run),
];

/// Runs every case at `resolution` and returns all rows, in the order of docs/physics.md §9.
///
/// The cases are independent and run in parallel. An engine error inside a case does not
/// stop the others: it becomes a single failing row naming the error.
pub fn run_all(resolution: Resolution) -> Vec<Row> {
    let results: Vec<Vec<Row>> = CASES
        .par_iter()
        .map(|(name, case)| match case(resolution) {
            Ok(rows) => rows,
            Err(e) => vec![Row::failed(name, &e.to_string())],
        })
        .collect();
    results.into_iter().flatten().collect()
}
