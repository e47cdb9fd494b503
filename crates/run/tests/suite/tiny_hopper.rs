//! A hopper a few particles wide, small enough to fill, settle and drain in seconds, shared
//! by the run tests.
//!
//! 250 spheres of 3 mm in a 50 mm × 100 mm slab with an 18 mm (6 d) centred outlet, wide
//! enough that arches are rare. The insertion band is only the top 30 mm, which holds
//! fewer than 250 particles at random insertion density, so the fill takes several batches
//! and can be interrupted midway.

use std::path::Path;

use case::{parse_case, Case};

const TINY_CASE: &str = concat!(
    include_str!("../data/tiny.toml"),
    "
[output]
checkpoint_interval = 0.05
plots = false
"
);

/// The tiny case, with `sets` (`key=value`, as `hopperflow run --set`) applied.
pub fn tiny_case(sets: &[&str]) -> Case {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    parse_case(TINY_CASE, "tiny.toml", &sets).expect("the tiny case is valid")
}

/// The bytes of output file `name` in `dir`, or a panic naming it.
pub fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{}/{name}: {e}", dir.display()))
}
