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
time_step = 3.4e-6

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
        "2afaaa9fa79eacc56c90357af6636b9ac03091683d6a7ac344fc99f042963040",
    ),
    (
        "composition.csv",
        "44871b2f8acbf32d32812b4003f46ad71f18eeed3842166e0b2e3a51c54d6fcf",
    ),
    (
        "crossings.csv",
        "d8aee2debb390a74885845bf2a7596c828b295f75d3a6fe2ebfbcf6a8abcfc8f",
    ),
    (
        "flow.csv",
        "03655227fd061540988aa95b6da0a7f11ee6e94c360bac1fe59254008633fafa",
    ),
    (
        "profiles.csv",
        "e59f90616894076593e4c47b01954aaa471f4b1e2ac6fb5f0d6b41620ca4c704",
    ),
    (
        "remaining.csv",
        "69e235bf887520e8e15c8f4c25882a7693476476bdfbac3c891528dc034a557f",
    ),
    (
        "residence.csv",
        "3dcd7db26d10273b0049c8d05ee338ea9c587d35449dabed5fccff95ef233673",
    ),
    (
        "summary.json",
        "9d48e0d6b530a3e980d2c94f3095b621af0edaf6a0543f52243d161db8777a31",
    ),
    (
        "wall_forces.csv",
        "3df270e7b0e3972632ced49f7f5b0ce6b2bf72e54bfe64951fbe15129d3be13e",
    ),
    (
        "wall_pressure.csv",
        "c1d01ed4421229c7f1453f3a95e93f8745fee704d282fd4484f9727a08d2cc75",
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
