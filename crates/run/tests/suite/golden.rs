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
    ("discharge_rate", "0.014726215563702162"),
    ("discharge_rate_error", "0.0006825996347391868"),
    ("steady_window", "[0.1,0.4]"),
    ("plateau_found", "true"),
    ("flux_check_rate", "0.014808782470793204"),
    ("flux_check_rate_profiles", "0.01448890550433107"),
    ("bulk_volume_fraction", "0.5282982661600516"),
    ("bulk_area_fraction", "0.799964745311489"),
    ("bed_height", "0.04420427983419389"),
    ("centre_velocity", "0.4629936994724564"),
    ("centre_area_fraction", "0.5860516616633855"),
    ("max_area_fraction", "0.5902493259431426"),
    ("max_area_fraction_position", "-0.08333333333333337"),
    ("stop_reason", "time_limit"),
    ("discharged_mass", "0.007563384313517446"),
    ("discharge_time", "0.6000000000000001"),
    ("fill_time", "0.19"),
    ("settled_kinetic_energy", "1.4356230833208067e-9"),
    ("settled", "true"),
];

/// SHA-256 of the output tables.
const GOLDEN_FILES: &[(&str, &str)] = &[
    (
        "flow.csv",
        "e80e4a48c6b85550d5ac11103c72e2bcef2ae9b0dcbeeed58d05cd7d01cecadb",
    ),
    (
        "profiles.csv",
        "43f8525edaa447d89a59810688a3ae20d2bf351e225d8110004bf25d01a89ec6",
    ),
    (
        "field.csv",
        "bb8d47f5cd9e9358b59d6fe78109d8aa5d3bafa675ae45fdb8a9509d1c8c6014",
    ),
    (
        "crossings.csv",
        "758e1496cf311563979cc840308758d8d72c7018537f78dedb74bec92b9447d3",
    ),
    (
        "wall_forces.csv",
        "3740abae6a4f5059d25a5ef840dd21547c483f47fa100b66d7fbbc1ced150b74",
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
