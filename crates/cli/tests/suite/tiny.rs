//! The tiny hopper of the library's run tests, for the command-line tests that start runs
//! from beds and packings: 250 spheres of 3 mm in a 50 mm slab, flat-bottomed, an 18 mm
//! outlet, no checkpoints, snapshots or plots.

/// The tiny case's text with its discharge cut to `time_limit` [s].
pub fn tiny_case(time_limit: f64) -> String {
    let base = include_str!("../../../run/tests/data/tiny.toml")
        .replace("time_limit = 0.6", &format!("time_limit = {time_limit:?}"));
    format!(
        "{base}
[output]
checkpoint_interval = 0.0
vtu_interval = 0.0
plots = false
"
    )
}
