//! A whole hopper run, pinned: the tiny hopper's fill, settle and discharge must reproduce
//! the recorded summary values and output tables bit for bit (W(t), the profiles, the
//! velocity field, every outlet crossing and the walls' loads). With the engine's own golden
//! (`crates/dem/tests/suite/golden.rs`) this makes "the same bits" after a change a test.
//!
//! When an issue changes the physics or the measurements on purpose, this test fails.
//! Then, and only then:
//! 1. run `cargo test -p hopperflow-run --test suite golden:: -- --nocapture`; the failure lists
//!    every value that moved with its new value;
//! 2. replace the constants below with the new ones;
//! 3. say in the commit message that the golden values were regenerated and which change
//!    moved them.

use crate::tiny_hopper;

use run::{run_case, RunOptions, RunOutcome};
use sha2::{Digest, Sha256};

/// Summary keys and their recorded values, as `summary.json` writes them (shortest
/// round-trip decimals, so string equality is bit equality).
const GOLDEN_SUMMARY: &[(&str, &str)] = &[
    ("discharge_rate", "0.016719918593864916"),
    ("discharge_rate_error", "0.0007906812513782637"),
    ("steady_window", "[0.12,0.38]"),
    ("plateau_found", "true"),
    ("flux_check_rate", "0.016563637540817647"),
    ("flux_check_rate_profiles", "0.016405686295569585"),
    ("bulk_volume_fraction", "0.5355600619121937"),
    ("bulk_area_fraction", "0.8111290510839163"),
    ("bed_height", "0.043824399357889746"),
    ("centre_velocity", "0.4751182718217796"),
    ("centre_area_fraction", "0.6088320172251867"),
    ("max_area_fraction", "0.6412125699549335"),
    ("max_area_fraction_position", "0.08333333333333326"),
    ("stop_reason", "time_limit"),
    ("discharged_mass", "0.00781078473498764"),
    ("discharge_time", "0.60048"),
    ("fill_time", "0.105084"),
    ("settled_kinetic_energy", "8.096330778510721e-9"),
    ("settled", "true"),
];

/// SHA-256 of the output tables.
const GOLDEN_FILES: &[(&str, &str)] = &[
    (
        "flow.csv",
        "dc1ccf18d3febf283dde92b507847427e48af34e64c2bb70b621928c3223397c",
    ),
    (
        "profiles.csv",
        "837caeb59198719edc1a5ac881cca0eb47c0e090ee20a2935123c172a2d768af",
    ),
    (
        "field.csv",
        "dbd20f95821d87e6d08bf6e946291e886ebd27cc2d2f37a8876fc42e27b1834d",
    ),
    (
        "crossings.csv",
        "e061c059b01bb37adf8025e608675e5fcd9a7c35c205b25d6f028090be5be0ba",
    ),
    (
        "wall_forces.csv",
        "a16f7f1c6d88ec8a78366c4c90897db51156e5989aa334f091d82f0fa2cb85df",
    ),
];

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
