//! A whole hopper run, pinned: the tiny hopper's fill, settle and discharge must reproduce
//! the recorded summary values and output files bit for bit. With the engine's own golden
//! (`crates/dem/tests/golden.rs`) this makes "the same bits" after a change a test.
//!
//! When an issue changes the physics or the measurements on purpose, this test fails.
//! Then, and only then:
//! 1. run `cargo test -p hopperflow-study --test golden -- --nocapture`; the failure lists
//!    every value that moved with its new value;
//! 2. replace the constants below with the new ones;
//! 3. say in the commit message that the golden values were regenerated and which change
//!    moved them.

mod tiny_hopper;

use sha2::{Digest, Sha256};
use study::run::{run_case, RunOptions, RunOutcome};

/// Summary keys and their recorded values, as `summary.json` writes them (shortest
/// round-trip decimals, so string equality is bit equality).
const GOLDEN_SUMMARY: &[(&str, &str)] = &[
    ("discharge_rate", "?"),
    ("discharge_rate_error", "?"),
    ("steady_window", "?"),
    ("plateau_found", "?"),
    ("flux_check_rate", "?"),
    ("flux_check_rate_profiles", "?"),
    ("bulk_volume_fraction", "?"),
    ("bulk_area_fraction", "?"),
    ("bed_height", "?"),
    ("centre_velocity", "?"),
    ("centre_area_fraction", "?"),
    ("max_area_fraction", "?"),
    ("max_area_fraction_position", "?"),
    ("stop_reason", "?"),
    ("discharged_mass", "?"),
    ("discharge_time", "?"),
    ("fill_time", "?"),
    ("settled_kinetic_energy", "?"),
    ("settled", "?"),
];

/// SHA-256 of the output tables.
const GOLDEN_FILES: &[(&str, &str)] =
    &[("flow.csv", "?"), ("profiles.csv", "?"), ("field.csv", "?")];

#[test]
fn tiny_hopper_run_reproduces_its_golden_outputs() {
    let case = tiny_hopper::tiny_case(&[]);
    let dir = tempfile::tempdir().expect("temporary directory");
    let options = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    let outcome = run_case(&case, dir.path(), &options).expect("the tiny hopper runs");
    assert!(
        matches!(outcome, RunOutcome::Finished(_)),
        "the run finished"
    );

    let summary: serde_json::Value =
        serde_json::from_slice(&tiny_hopper::read(dir.path(), "summary.json"))
            .expect("summary.json parses");
    let mut moved = Vec::new();
    for (key, golden) in GOLDEN_SUMMARY {
        let value = match &summary[*key] {
            serde_json::Value::String(text) => text.clone(),
            other => other.to_string(),
        };
        if value != *golden {
            moved.push(format!("    (\"{key}\", \"{value}\"), // was {golden}"));
        }
    }
    for (name, golden) in GOLDEN_FILES {
        let digest: String = Sha256::digest(tiny_hopper::read(dir.path(), name))
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        if digest != *golden {
            moved.push(format!("    (\"{name}\", \"{digest}\"), // was {golden}"));
        }
    }
    assert!(
        !GOLDEN_SUMMARY.is_empty() && !GOLDEN_FILES.is_empty() && moved.is_empty(),
        "the tiny hopper's outputs changed; if the physics was changed on purpose, \
         regenerate as the header of this file says. Moved:\n{}",
        moved.join("\n")
    );
}
