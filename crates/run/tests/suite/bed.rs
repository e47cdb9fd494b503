//! A settled bed saved when the gate opens and reused (`RunOptions::save_bed`,
//! `run_case_from` with `Start::Bed`; docs/user-guide.md §5).
//!
//! The issue's must-show: one bed discharged through three orifices gives, bit for bit, what
//! runs from copies of that bed give (a run from a bed depends on the bed's content only,
//! not on where it lies or what ran from it before), and the bed's own case discharges from
//! it exactly as the run that saved it. Then the refusals: a case that changes a key that
//! made the bed, an outlet moved under inclined walls, a damaged bed file.

use std::path::{Path, PathBuf};

use crate::tiny_hopper;

use case::{parse_case, Case};
use files::CaseSummary;
use files::{StartKind, BED_CASE_FILE, BED_FILE, START_FILE, SUMMARY_FILE};
use run::{
    check_bed_case, read_bed, run_case, run_case_from, BedError, RunError, RunOptions, RunOutcome,
    Start,
};
use tiny_hopper::{read, tiny_case};

/// The outputs that depend on the simulated particles, all compared byte for byte.
const OUTPUTS: [&str; 8] = [
    SUMMARY_FILE,
    "flow.csv",
    "crossings.csv",
    "remaining.csv",
    "wall_forces.csv",
    "profiles.csv",
    "field.csv",
    "case.toml",
];

fn options(save_bed: Option<PathBuf>) -> RunOptions {
    RunOptions {
        resume: false,
        pictures: false,
        save_bed,
        ..RunOptions::default()
    }
}

fn finished(outcome: Result<RunOutcome, RunError>, what: &str) -> CaseSummary {
    match outcome {
        Ok(RunOutcome::Finished(summary)) => *summary,
        Ok(RunOutcome::Interrupted) => panic!("{what}: interrupted without a chunk limit"),
        Err(e) => panic!("{what}: {e}"),
    }
}

/// Asserts that `name` is in both folders or in neither (a silo writes no `field.csv`), and
/// the same bytes where it is.
fn assert_same_file(a: &Path, b: &Path, name: &str, what: &str) {
    let present = a.join(name).exists();
    assert_eq!(
        present,
        b.join(name).exists(),
        "{what}: {name} in one folder only"
    );
    if !present {
        return;
    }
    let (left, right) = (read(a, name), read(b, name));
    assert!(
        left == right,
        "{what}: {name} differs:\n--- {}\n{}\n--- {}\n{}",
        a.display(),
        String::from_utf8_lossy(&left),
        b.display(),
        String::from_utf8_lossy(&right)
    );
}

fn json(dir: &Path, name: &str) -> serde_json::Value {
    serde_json::from_slice(&read(dir, name)).expect("JSON")
}

/// The data lines of a CSV whose first column (time [s]) is after `t`.
fn rows_after(dir: &Path, name: &str, t: f64) -> Vec<String> {
    let text = String::from_utf8(read(dir, name)).expect("UTF-8");
    text.lines()
        .skip(1)
        .filter(|line| {
            let time: f64 = line.split(',').next().unwrap().parse().expect("a time");
            time > t
        })
        .map(str::to_string)
        .collect()
}

/// A copy of the bed folder `from` at `to`: the same content in another place.
fn copy_bed(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for name in [BED_FILE, BED_CASE_FILE] {
        std::fs::copy(from.join(name), to.join(name)).unwrap();
    }
}

#[test]
fn one_bed_through_three_orifices_equals_runs_from_its_copies_and_repeats_its_own_run() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = |name: &str| root.path().join(name);
    let base = tiny_case(&[]);
    let started = std::time::Instant::now();
    let original = finished(
        run_case(&base, &dir("original"), &options(Some(dir("bed")))),
        "the run that saves the bed",
    );
    eprintln!("saving run: {:.1} s wall", started.elapsed().as_secs_f64());
    let bed = read_bed(&dir("bed")).expect("the saved bed reads back");
    // The bed is the state at the opening: the saving run opened its gate at the bed's time.
    assert_eq!(bed.header().time, original.fill_time);
    assert_eq!(bed.header().particles, base.particles.count);
    assert_eq!(bed.case_text(), base.to_toml_string());
    assert!(
        original.settled,
        "the tiny bed must settle to test reuse of a settled bed"
    );

    // The bed's own case: the saving run's discharge, bit for bit. Only the record of the
    // start tells the summaries apart, and the wall loads of the fill and settling, which
    // belong to the saving run.
    let started = std::time::Instant::now();
    let same = finished(
        run_case_from(
            &base,
            &dir("same"),
            &options(None),
            &Start::Bed(Box::new(bed.clone())),
        ),
        "the bed's own case",
    );
    eprintln!(
        "discharge from the bed: {:.1} s wall",
        started.elapsed().as_secs_f64()
    );
    for name in [
        "flow.csv",
        "crossings.csv",
        "remaining.csv",
        "profiles.csv",
        "field.csv",
        "case.toml",
    ] {
        assert_same_file(
            &dir("original"),
            &dir("same"),
            name,
            "own case from the bed",
        );
    }
    assert_eq!(
        rows_after(&dir("original"), "wall_forces.csv", original.fill_time),
        rows_after(&dir("same"), "wall_forces.csv", 0.0),
        "the wall loads from the opening on"
    );
    let record = same
        .start
        .clone()
        .expect("a run from a bed records its start");
    assert_eq!(record.kind, StartKind::Bed);
    assert_eq!(record.sha256, bed.sha256());
    let mut without_start = json(&dir("same"), SUMMARY_FILE);
    without_start
        .as_object_mut()
        .expect("an object")
        .remove("start");
    assert_eq!(without_start, json(&dir("original"), SUMMARY_FILE));
    let start = json(&dir("same"), START_FILE);
    assert_eq!(start["walls_rebuilt"], serde_json::json!([]));
    assert_eq!(start["changed_keys"], serde_json::json!([]));

    // Three orifices, each run from the bed and from a copy of it in another folder.
    let mut rates = Vec::new();
    for (k, width) in [0.018, 0.024, 0.030].into_iter().enumerate() {
        let case = tiny_case(&[&format!("geometry.outlet_width={width}")]);
        let copy = dir(&format!("copy{k}"));
        copy_bed(&dir("bed"), &copy);
        let (a, b) = (dir(&format!("bed{k}")), dir(&format!("copy{k}-run")));
        let from_bed = Start::Bed(Box::new(read_bed(&dir("bed")).unwrap()));
        let from_copy = Start::Bed(Box::new(read_bed(&copy).unwrap()));
        let summary = finished(
            run_case_from(&case, &a, &options(None), &from_bed),
            "from the bed",
        );
        finished(
            run_case_from(&case, &b, &options(None), &from_copy),
            "from a copy",
        );
        for name in OUTPUTS {
            assert_same_file(&a, &b, name, &format!("D = {width} m"));
        }
        let (start_a, start_b) = (json(&a, START_FILE), json(&b, START_FILE));
        assert_eq!(start_a["start"], start_b["start"]);
        let rebuilt = if k == 0 {
            serde_json::json!([])
        } else {
            serde_json::json!(["plate_left", "plate_right", "gate"])
        };
        assert_eq!(start_a["walls_rebuilt"], rebuilt, "D = {width} m");
        assert_eq!(summary.fill_time, original.fill_time);
        eprintln!(
            "D = {width} m: W = {:.4} kg/s, {:?} after {:.3} s",
            summary.discharge_rate, summary.stop_reason, summary.discharge_time
        );
        rates.push(summary.discharge_rate);
    }
    // The first orifice is the bed's own: its run repeats the saving run's discharge.
    assert_same_file(&dir("same"), &dir("bed0"), "flow.csv", "D of the bed");
    // The outlet does change the discharge: W grows with D (2D Beverloo: W ∝ (D − k d)^1.5,
    // a factor 1.4 and more from one width to the next, against some 10 % of noise in a
    // bed of 250 spheres).
    assert!(
        rates.windows(2).all(|w| w[1] > w[0]),
        "W must grow with the outlet: {rates:?}"
    );

    // A case that changes a particle key is refused before anything is written.
    let bigger = tiny_case(&["particles.diameter=0.0029"]);
    let refused = run_case_from(
        &bigger,
        &dir("refused"),
        &options(None),
        &Start::Bed(Box::new(bed.clone())),
    );
    let Err(RunError::Bed(BedError::OtherInputs { changes, .. })) = refused else {
        panic!("a changed particle diameter must be refused, got {refused:?}")
    };
    assert!(changes
        .iter()
        .any(|c| c.to_string() == "particles.diameter: 0.003 -> 0.0029"));
    assert!(!dir("refused").exists(), "a refused run created its folder");

    // A damaged bed is told apart from a foreign file, and never read.
    let bytes = std::fs::read(dir("bed").join(BED_FILE)).unwrap();
    let damaged = dir("damaged");
    std::fs::create_dir_all(&damaged).unwrap();
    let file = damaged.join(BED_FILE);
    std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
    assert!(matches!(
        read_bed(&damaged),
        Err(BedError::Truncated { .. })
    ));
    let mut flipped = bytes.clone();
    flipped[100] ^= 1;
    std::fs::write(&file, &flipped).unwrap();
    assert!(matches!(read_bed(&damaged), Err(BedError::Corrupt(_))));
    std::fs::write(&file, b"not a bed").unwrap();
    let err = read_bed(&damaged).unwrap_err();
    assert!(matches!(err, BedError::Foreign(_)), "{err:?}");
    assert!(matches!(
        read_bed(&dir("nowhere")),
        Err(BedError::Missing(_))
    ));
}

/// A flat-bottomed silo of 200 spheres of 2 mm, 24 mm across: small enough to fill and
/// settle in seconds. Its bottom is a triangle mesh with the orifice cut out.
const TINY_SILO: &str = r#"
version = 1
seed = 5

[geometry]
kind = "cylinder"
radius = 0.012
height = 0.06
outlet_diameter = 0.01
hopper_angle_deg = 90.0
walls = "smooth"
mesh_segments = 24

[particles]
count = 200
diameter = 0.002

[protocol]
settle_kinetic_energy = 1.0e-9
max_settle_time = 0.2
fill_top = 0.04
clog_timeout = 0.05
time_limit = 0.1

[output]
checkpoint_interval = 0.0
plots = false
"#;

fn tiny_silo(sets: &[&str]) -> Case {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    parse_case(TINY_SILO, "tiny-silo.toml", &sets).expect("the tiny silo is valid")
}

#[test]
fn a_flat_silo_bed_through_a_wider_orifice_rebuilds_its_bottom_and_gate_only() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = |name: &str| root.path().join(name);
    let started = std::time::Instant::now();
    finished(
        run_case(
            &tiny_silo(&[]),
            &dir("original"),
            &options(Some(dir("bed"))),
        ),
        "the silo that saves its bed",
    );
    eprintln!(
        "silo saving run: {:.1} s wall",
        started.elapsed().as_secs_f64()
    );
    let wider = tiny_silo(&["geometry.outlet_diameter=0.014"]);
    copy_bed(&dir("bed"), &dir("copy"));
    let mut summaries = Vec::new();
    for (source, out) in [("bed", "a"), ("copy", "b")] {
        let bed = read_bed(&dir(source)).unwrap();
        summaries.push(finished(
            run_case_from(
                &wider,
                &dir(out),
                &options(None),
                &Start::Bed(Box::new(bed)),
            ),
            "the wider orifice",
        ));
    }
    for name in OUTPUTS {
        assert_same_file(&dir("a"), &dir("b"), name, "silo from a copy");
    }
    let start = json(&dir("a"), START_FILE);
    // The cylinder stays, with the histories of its contacts; the flat bottom (its hole
    // widened) and the gate are new.
    assert_eq!(
        start["walls_rebuilt"],
        serde_json::json!(["bottom", "gate"])
    );
    assert_eq!(
        start["changed_keys"],
        serde_json::json!(["geometry.outlet_diameter: 0.01 -> 0.014"])
    );
    assert!(
        summaries[0].discharged_mass > 0.0,
        "particles must leave through the new orifice"
    );
}

#[test]
fn only_the_outlet_discharge_measure_and_output_keys_may_change_under_a_bed() {
    let bed = Path::new("beds/tiny/bed.bin");
    let base = tiny_case(&[]);
    let text = base.to_toml_string();
    let refused = |case: &Case| match check_bed_case(bed, &text, case) {
        Err(BedError::OtherInputs { changes, .. }) => {
            changes.iter().map(ToString::to_string).collect::<Vec<_>>()
        }
        other => panic!("expected a refusal, got {other:?}"),
    };
    // Every key that made the bed is named, with the bed's value first.
    let changed = tiny_case(&[
        "seed=12",
        "particles.diameter=0.0029",
        "wall.friction=0.3",
        "protocol.fill_top=0.09",
        "time.time_step=2e-6",
    ]);
    let names = refused(&changed);
    for expected in [
        "seed: 11 -> 12",
        "particles.diameter: 0.003 -> 0.0029",
        "wall.friction: 0.5 -> 0.3",
        "protocol.fill_top: 0.1 -> 0.09",
        "time.time_step: 0.0000045 -> 0.000002",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "`{expected}` not among {names:?}"
        );
    }
    let message = check_bed_case(bed, &text, &changed)
        .unwrap_err()
        .to_string();
    assert!(message.starts_with("beds/tiny/bed.bin: the bed was settled under other inputs"));
    assert!(message.contains("seed: 11 -> 12"), "{message}");

    // The outlet, the discharge rules and the measurement and output keys may change.
    let allowed = tiny_case(&[
        "geometry.outlet_width=0.03",
        "geometry.outlet_offset=0.005",
        "protocol.time_limit=2",
        "protocol.stop_fraction=0.7",
        "measure.x_bin_width=0.001",
        "output.vtu_interval=0",
    ]);
    let reuse = check_bed_case(bed, &text, &allowed).expect("allowed changes");
    assert!(reuse.outlet_changed);
    assert_eq!(reuse.changes.len(), 6, "{:?}", reuse.changes);
    let unchanged = check_bed_case(bed, &text, &base).expect("the bed's own case");
    assert!(!unchanged.outlet_changed && unchanged.changes.is_empty());

    // Under inclined plates the outlet cannot move: the plates would move with it.
    let funnel = tiny_case(&["geometry.hopper_angle_deg=60"]);
    let wider_funnel = tiny_case(&[
        "geometry.hopper_angle_deg=60",
        "geometry.outlet_width=0.024",
    ]);
    let err = check_bed_case(bed, &funnel.to_toml_string(), &wider_funnel).unwrap_err();
    assert!(
        matches!(&err, BedError::WallsWouldMove { angle_deg, .. } if *angle_deg == 60.0),
        "{err:?}"
    );
    assert!(
        err.to_string()
            .contains("geometry.outlet_width: 0.018 -> 0.024"),
        "{err}"
    );
    // So does a cone's orifice, and another container kind is another bed.
    let cone = tiny_silo(&["geometry.hopper_angle_deg=45"]);
    let wider_cone = tiny_silo(&[
        "geometry.hopper_angle_deg=45",
        "geometry.outlet_diameter=0.012",
    ]);
    assert!(matches!(
        check_bed_case(bed, &cone.to_toml_string(), &wider_cone),
        Err(BedError::WallsWouldMove {
            kind: "cylinder",
            ..
        })
    ));
    let names = refused(&tiny_silo(&[]));
    assert!(
        names
            .iter()
            .any(|n| n == "geometry.kind: (absent) -> \"cylinder\""),
        "{names:?}"
    );
}
