//! The tiny hopper of the library's run tests, for the command-line tests that start runs
//! from beds and packings: 250 spheres of 3 mm in a 50 mm slab, flat-bottomed, an 18 mm
//! outlet, no checkpoints, snapshots or plots.

/// The tiny case's text with its discharge cut to `time_limit` [s].
pub fn tiny_case(time_limit: f64) -> String {
    format!(
        r#"
version = 1
seed = 11

[geometry]
width = 0.05
height = 0.1
outlet_width = 0.018

[particles]
count = 250
diameter = 0.003

[protocol]
settle_kinetic_energy = 1.0e-8
max_settle_time = 0.15
fill_bottom = 0.07
clog_timeout = 0.1
time_limit = {time_limit:?}

[output]
checkpoint_interval = 0.0
vtu_interval = 0.0
plots = false
"#
    )
}
