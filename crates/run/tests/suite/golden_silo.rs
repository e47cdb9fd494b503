//! A whole silo run, pinned: a small cone-bottomed cylinder filled with a two-component
//! mixture, settled and discharged through the whole protocol on two threads, must reproduce
//! the recorded bytes of every output file: the summary (the radial fits and the Janssen fit
//! of the settled bed included), W(t), the crossings, the radial profiles, N(t), the wall
//! forces and pressures, and the outflow's composition. With the engine's silo golden
//! (`crates/dem/tests/suite/golden_silo.rs`) this makes "the same bits" of the 3D capability a test.
//!
//! When an issue changes the physics or the measurements on purpose, this test fails.
//! Then, and only then:
//! 1. run `cargo test -p hopperflow-run --test suite golden_silo:: -- --nocapture`; the failure
//!    lists every file that moved with its new digest;
//! 2. replace the constants below with the new ones;
//! 3. say in the commit message that the golden values were regenerated and which change
//!    moved them.

use std::collections::BTreeMap;
use std::path::Path;

use case::{parse_case, Case};
use run::{run_case, RunOptions, RunOutcome};
use sha2::{Digest, Sha256};

/// 1800 spheres of 2 and 4 mm, half the mass each, in a cylinder of R = 16 mm over a 45°
/// cone to a 16 mm orifice (4 large, 8 small diameters). The small spheres are of material
/// `a`, the large of `b`; the table lists each with itself and with the steel walls but not
/// (a, b), which the mixing rules give (docs/physics.md §1.2). The settled bed stands 30 mm,
/// so three zones of the cylinder lie between the cone and two diameters below its surface:
/// the fewest that the Janssen fit takes. The discharge stops at 0.25 s, past the steady
/// window's end (70 % of the fill out at about 0.2 s).
const CASE: &str = r#"
version = 1
seed = 1

[geometry]
kind = "cylinder"
radius = 0.016
height = 0.06
outlet_diameter = 0.016
hopper_angle_deg = 45.0

[materials.a]
density = 2500.0
youngs_modulus = 2.5e8
poisson_ratio = 0.25

[materials.b]
density = 2000.0
youngs_modulus = 2.0e8
poisson_ratio = 0.3

[materials.steel]
density = 7800.0
youngs_modulus = 2.0e11
poisson_ratio = 0.3

[[pairs]]
materials = ["a", "a"]
restitution = 0.3
friction = 0.5
rolling_friction = 0.01

[[pairs]]
materials = ["b", "b"]
restitution = 0.5
friction = 0.4
rolling_friction = 0.02

[[pairs]]
materials = ["a", "steel"]
restitution = 0.4
friction = 0.3
rolling_friction = 0.01

[[pairs]]
materials = ["b", "steel"]
restitution = 0.4
friction = 0.25
rolling_friction = 0.01

[particles]
count = 1800
fraction_by = "mass"

[[particles.components]]
name = "small"
diameter = 0.002
material = "a"
fraction = 0.5

[[particles.components]]
name = "large"
diameter = 0.004
material = "b"
fraction = 0.5

[wall]
material = "steel"

[time]
time_step = 2.5e-6

[protocol]
settle_kinetic_energy = 1.0e-8
max_settle_time = 0.15
clog_timeout = 0.1
time_limit = 0.25

[measure]
rate_bin_width = 0.02

[output]
vtu_interval = 0.0
checkpoint_interval = 0.0
plots = false
"#;

/// SHA-256 of every file the run writes but `timing.json` (wall-clock figures only).
const GOLDEN_FILES: &[(&str, &str)] = &[
    (
        "case.toml",
        "4e19b92862de4e19188345a74b9663b654ea215341c0db10ca597b6a2ad5e2e8",
    ),
    (
        "composition.csv",
        "2487338bf629dd1dd5fb24cf801d5f093aec734165d03bd03f6d2ab7656130f9",
    ),
    (
        "crossings.csv",
        "932619e25ccc39c5b4a4dd830acc67eb740b11ec7f7f24a237335347aab9a112",
    ),
    (
        "flow.csv",
        "5b856b0b1b4bafcfdac1ad8ee0aafa1c2e11a220cd09db9087490727d68c587d",
    ),
    (
        "profiles.csv",
        "b6d2cdbc8ebb1d4f215068c36bf35d95f6e541fb2d2ad8245247f66ea26416bd",
    ),
    (
        "remaining.csv",
        "5c1b46412e0996d40610658991c87cba05c028fc738b27ad00881145d2a05943",
    ),
    (
        "summary.json",
        "c9e95668f35a77daac159ed7caed5abc7acd0fd23ab8e03b0df6dca47686b160",
    ),
    (
        "wall_forces.csv",
        "9109612b1603e953b4b9245bdf4272183d240c55f602b7a0a308738e54eaeb63",
    ),
    (
        "wall_pressure.csv",
        "c352f0656c6d68cea5caa7a3019c3b994b7b8ff050d69840d070b3e2d504021e",
    ),
];

fn case() -> Case {
    parse_case(CASE, "golden-silo.toml", &[]).expect("the golden silo is a valid case")
}

fn digest(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every file of `dir` but `timing.json`, by name, with its SHA-256.
fn digests(dir: &Path) -> BTreeMap<String, String> {
    std::fs::read_dir(dir)
        .expect("the run's folder")
        .map(|entry| entry.expect("an entry").path())
        .filter(|path| path.file_name().is_some_and(|n| n != "timing.json"))
        .map(|path| {
            let name = path
                .file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, digest(&bytes))
        })
        .collect()
}

#[test]
fn silo_mixture_run_reproduces_its_golden_outputs_on_two_threads() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let options = RunOptions {
        threads: 2,
        resume: false,
        ..RunOptions::default()
    };
    let outcome = run_case(&case(), dir.path(), &options).expect("the golden silo runs");
    let RunOutcome::Finished(summary) = outcome else {
        panic!("the run finished")
    };

    // What the golden must hold for it to pin the silo's measurements: both fits exist and
    // the mixture's composition is among the files.
    assert!(
        summary.radial_fit.is_some(),
        "the radial profiles are fitted"
    );
    let janssen = summary.janssen.unwrap_or_else(|| {
        panic!(
            "the settled bed's wall pressure is fitted: {:?}",
            summary.janssen_not_fitted
        )
    });
    assert!(janssen.zones >= 3, "{janssen:?}");

    let found = digests(dir.path());
    let golden: BTreeMap<String, String> = GOLDEN_FILES
        .iter()
        .map(|(n, d)| (n.to_string(), d.to_string()))
        .collect();
    assert!(
        found.contains_key("composition.csv") && found.contains_key("wall_pressure.csv"),
        "the silo writes its mixture's and its walls' files: {:?}",
        found.keys()
    );
    let moved: Vec<String> = found
        .iter()
        .filter(|(name, d)| golden.get(*name) != Some(d))
        .map(|(name, d)| {
            let was = golden.get(name).map_or("absent", String::as_str);
            format!("    (\"{name}\", \"{d}\"), // was {was}")
        })
        .chain(
            golden
                .keys()
                .filter(|name| !found.contains_key(*name))
                .map(|name| format!("    {name}: no longer written")),
        )
        .collect();
    assert!(
        moved.is_empty(),
        "the golden silo's outputs changed; if the physics or the measurements were changed on \
         purpose, regenerate as the header of this file says. Moved:\n{}",
        moved.join("\n")
    );
}
