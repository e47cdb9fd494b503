//! `hopperflow bench --case silo --case-file FILE --packing FILE` through the binary: a case
//! file started from a packing is timed with the packing's particles, and its settled bed is
//! cached under a name no other packing shares; a discharge that stops inside the window is an
//! error, not a hang; bad inputs for the silo's options are refused with exit 2, a message
//! naming the option and the file, and nothing timed or cached.

use crate::run_cli;
use run_cli::{hopperflow, utf8};
use std::path::{Path, PathBuf};
use std::process::Output;

/// A small silo: a flat-bottomed cylinder of radius 20 mm with a 12 mm orifice (4 d), spheres
/// of 3 mm of the paper's material (Δt = 2.5 µs). Through 4 d about 400 spheres leave per
/// second (Beverloo), so a few hundred are still in it at the end of the benchmark's window
/// (0.05–0.08 s after the opening), and a sphere falls at most g·(0.08 s)²/2 = 31 mm below
/// the orifice by then: with deletion 0.1 m below it, none is deleted in the window. The
/// settling threshold is raised so that the bed settles in the shortest time the protocol
/// allows (0.05 s).
const TINY_SILO: &str = r#"
version = 1
seed = 3

[geometry]
kind = "cylinder"
radius = 0.02
height = 0.1
outlet_diameter = 0.012
hopper_angle_deg = 90.0

[particles]
count = 1                  # the packing's count replaces it
diameter = 0.003

[protocol]
settle_kinetic_energy = 1.0e-7
max_settle_time = 0.2
deletion_depth = 0.1
clog_timeout = 0.3
time_limit = 0.5

[output]
checkpoint_interval = 0.0
vtu_interval = 0.0
plots = false
"#;

/// Spheres in the test packing.
const PACKED: usize = 300;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("writable scratch file");
    path
}

/// `PACKED` spheres of the tiny silo on a square lattice 1 % wider than a diameter, layer by
/// layer from 0.1 mm above the gate, each at least 0.1 mm from the cylinder: at rest and
/// touching nothing. `lift` [m] raises the last sphere (another packing of the same count).
fn lattice_csv(lift: f64) -> String {
    let (r, spacing) = (1.5e-3, 3.03e-3);
    let reach = 0.02 - r - 1e-4;
    let mut text = String::from("x,y,z,radius,material\n");
    let mut placed = 0;
    'layers: for layer in 0.. {
        let z = r + 1e-4 + layer as f64 * spacing;
        for i in -7..=7 {
            for j in -7..=7 {
                let (x, y) = (i as f64 * spacing, j as f64 * spacing);
                if x.hypot(y) > reach {
                    continue;
                }
                placed += 1;
                let z = if placed == PACKED { z + lift } else { z };
                text.push_str(&format!("{x:?},{y:?},{z:?},{r:?},glass\n"));
                if placed == PACKED {
                    break 'layers;
                }
            }
        }
    }
    text
}

/// The settled-bed caches in `dir`.
fn caches(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("silo-") && n.ends_with(".bin"))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

fn bench_json(args: &[&str]) -> serde_json::Value {
    let output = hopperflow(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "bench failed:\n{stderr}");
    serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!(
            "bench printed no JSON object ({e}):\n{}",
            String::from_utf8_lossy(&output.stdout)
        )
    })
}

#[test]
fn a_case_file_started_from_a_packing_is_timed_with_the_packings_particles() {
    let root = tempfile::tempdir().expect("temporary directory");
    let case = write(root.path(), "tiny-silo.toml", TINY_SILO);
    let packing = write(root.path(), "lattice.csv", &lattice_csv(0.0));
    let cache_dir = root.path().join("cache");
    let cache = cache_dir.join("hopper.bin");
    let args = |packing: &Path| {
        [
            "bench",
            "--case",
            "silo",
            "--case-file",
            utf8(&case),
            "--packing",
            utf8(packing),
            "--threads",
            "1",
            "--json",
            "--cache",
            utf8(&cache),
        ]
        .map(str::to_string)
    };
    let first_args = args(&packing);
    let first_args: Vec<&str> = first_args.iter().map(String::as_str).collect();
    let first = bench_json(&first_args);
    // Every sphere of the packing is in the window: the file's count (1) was replaced by the
    // packing's, and none left the run (the deletion plane is out of reach, see TINY_SILO).
    // The mean over the window is an exact integer then, so the comparison is exact.
    assert_eq!(first["particles"], PACKED, "{first:#}");
    assert_eq!(first["case"], "silo:tiny-silo");
    let ns = first["ns_per_particle_step"].as_f64().expect("a timing");
    assert!(ns.is_finite() && ns > 0.0, "{first:#}");
    // The window is the silo benchmark's 0.03 s: 12 000 steps of 2.5 µs, up to the last
    // protocol chunk (the window ends on a chunk's end, at most one chunk late).
    let steps = first["steps"].as_u64().expect("a step count");
    assert!((12_000..12_500).contains(&steps), "{steps} steps");
    let cached = caches(&cache_dir);
    assert_eq!(cached.len(), 1, "{cached:?}");
    assert!(cached[0].starts_with("silo-n300-smooth-"), "{cached:?}");

    // The same inputs find the cache and time the same discharge: the engine is
    // deterministic, so the contacts over the window agree to the bit.
    let again = bench_json(&first_args);
    assert_eq!(caches(&cache_dir), cached);
    assert_eq!(
        again["contacts_per_particle"],
        first["contacts_per_particle"]
    );

    // A packing of the same count with one sphere 1 mm higher is another bed: it gets a
    // cache of its own instead of the first one's.
    let moved = write(root.path(), "moved.csv", &lattice_csv(1e-3));
    let moved_args = args(&moved);
    let moved_args: Vec<&str> = moved_args.iter().map(String::as_str).collect();
    let other = bench_json(&moved_args);
    assert_eq!(other["particles"], PACKED);
    assert_eq!(caches(&cache_dir).len(), 2, "{:?}", caches(&cache_dir));
}

#[test]
fn a_discharge_that_stops_inside_the_window_fails_instead_of_hanging() {
    // A finished run takes no more steps, so a window that outlasts the discharge could never
    // be timed: the benchmark reports it (exit 1, a run-time failure, not bad input). The
    // override goes through --set, as for `run`.
    let root = tempfile::tempdir().expect("temporary directory");
    let case = write(root.path(), "tiny-silo.toml", TINY_SILO);
    let packing = write(root.path(), "lattice.csv", &lattice_csv(0.0));
    let cache = root.path().join("cache").join("hopper.bin");
    let output = hopperflow(&[
        "bench",
        "--case-file",
        utf8(&case),
        "--packing",
        utf8(&packing),
        "--set",
        "protocol.time_limit=0.06",
        "--threads",
        "1",
        "--json",
        "--cache",
        utf8(&cache),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for fragment in [
        "stopped (TimeLimit) 0.0600 s after the gate opened",
        "before the end of the benchmark window (0.0500-0.0800 s",
    ] {
        assert!(stderr.contains(fragment), "lacks `{fragment}`:\n{stderr}");
    }
}

/// Asserts exit code 2, no panic, every fragment in stderr, and that nothing was cached in
/// `cache_dir`.
fn assert_refused(output: &Output, cache_dir: &Path, what: &str, fragments: &[&str]) {
    run_cli::assert_refused(output, what, fragments);
    assert!(
        !cache_dir.exists(),
        "{what}: bad input wrote {}",
        cache_dir.display()
    );
    assert!(output.stdout.is_empty(), "{what}: printed a result");
}

#[test]
fn bad_silo_inputs_are_refused_naming_the_option_and_the_file() {
    let root = tempfile::tempdir().expect("temporary directory");
    let case = write(root.path(), "tiny-silo.toml", TINY_SILO);
    let packing = write(root.path(), "lattice.csv", &lattice_csv(0.0));
    let cache_dir = root.path().join("cache");
    let cache = cache_dir.join("hopper.bin");
    let bench = |extra: &[&str]| {
        let mut args = vec!["bench", "--threads", "1", "--json", "--cache", utf8(&cache)];
        args.extend_from_slice(extra);
        hopperflow(&args)
    };

    let missing = root.path().join("missing.toml");
    assert_refused(
        &bench(&["--case", "silo", "--case-file", utf8(&missing)]),
        &cache_dir,
        "a missing case file",
        &["--case-file", utf8(&missing), "cannot read the file"],
    );
    // A key out of range: the file, its line and the key, as `run` names them.
    let bad = write(
        root.path(),
        "bad.toml",
        &TINY_SILO.replace("radius = 0.02", "radius = -0.02"),
    );
    assert_refused(
        &bench(&["--case", "silo", "--case-file", utf8(&bad)]),
        &cache_dir,
        "a case file with a negative radius",
        &[
            "--case-file",
            &format!("{}:", utf8(&bad)),
            "geometry.radius",
        ],
    );
    // A packing whose second sphere has no number for x: the file and its line.
    let malformed = write(
        root.path(),
        "malformed.csv",
        &lattice_csv(0.0).replacen("\n0.0,", "\nabc,", 1),
    );
    assert_refused(
        &bench(&[
            "--case",
            "silo",
            "--case-file",
            utf8(&case),
            "--packing",
            utf8(&malformed),
        ]),
        &cache_dir,
        "a malformed packing",
        &[
            "--packing",
            &format!("{} line", utf8(&malformed)),
            "`abc` is not a number",
        ],
    );
    // A packing that is not in the case's container: the built-in silo's cone is far wider
    // than the tiny silo, but a sphere 1 m up lies above its top.
    let above = write(
        root.path(),
        "above.csv",
        "x,y,z,radius,material\n0.0,0.0,1.0,0.002,M1\n",
    );
    assert_refused(
        &bench(&["--case", "silo", "--packing", utf8(&above)]),
        &cache_dir,
        "a packing above the built-in silo",
        &["--packing", utf8(&above), "lies outside the cylinder"],
    );
    assert_refused(
        &bench(&["--case", "silo", "--meshed", "--case-file", utf8(&case)]),
        &cache_dir,
        "--meshed with --case-file",
        &["--meshed", "--case-file"],
    );
    assert_refused(
        &bench(&[
            "--case",
            "silo",
            "--particles",
            "500",
            "--packing",
            utf8(&packing),
        ]),
        &cache_dir,
        "--particles with --packing",
        &["--particles", "--packing"],
    );
    for case_name in ["bed", "hopper"] {
        assert_refused(
            &bench(&["--case", case_name, "--case-file", utf8(&case)]),
            &cache_dir,
            "--case-file with another --case",
            &[
                "--case-file",
                "--case silo only",
                &format!("--case {case_name}"),
            ],
        );
    }
}
