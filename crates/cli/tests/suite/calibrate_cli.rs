//! `hopperflow calibrate` at the command line: bad calibration files exit 2 having written
//! nothing; `--check` reads a good one without running it. (The loop itself is tested with
//! a stand-in simulation in calibration_loop.rs; the round trip with real runs is
//! `calibration_round_trip_recovers_the_rolling_friction` in validation.rs, ignored for its
//! length.)

use crate::run_cli::{assert_status, hopperflow, stderr_of, utf8};

const CASE: &str = "version = 1\n[particles]\ncount = 200\n";

#[test]
fn a_bad_calibration_file_exits_two_naming_the_key_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("test.toml"), CASE).unwrap();
    let file = dir.path().join("cal.toml");
    std::fs::write(
        &file,
        "version = 1\nname = \"glass\"\n[[parameters]]\nkey = \"contact.rolling_friction\"\nmin = -0.1\nmax = 0.2\n\
         [[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.001\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let output = hopperflow(&["calibrate", utf8(&file), "--out", utf8(&out)]);
    assert_status(&output, 2, "negative rolling friction in the range");
    let stderr = stderr_of(&output);
    assert!(
        stderr.contains("cal.toml") && stderr.contains("contact.rolling_friction = -0.1"),
        "{stderr}"
    );
    assert!(
        !out.exists(),
        "a refused calibration wrote {}",
        out.display()
    );
}

#[test]
fn check_reads_a_good_calibration_file_without_running_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("test.toml"), CASE).unwrap();
    let file = dir.path().join("cal.toml");
    std::fs::write(
        &file,
        "version = 1\nname = \"glass\"\n[[parameters]]\nkey = \"contact.rolling_friction\"\nmin = 0.0\nmax = 0.2\n\
         [[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.001\n",
    )
    .unwrap();
    let output = hopperflow(&["calibrate", utf8(&file), "--check"]);
    assert_status(&output, 0, "a good calibration file");
    assert!(String::from_utf8_lossy(&output.stdout).contains("1 parameter(s), 1 target(s)"));
    assert!(!dir.path().join("calibration-glass").exists());
}

#[test]
fn slurm_writes_the_first_rounds_array_and_the_job_that_continues_the_chain() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("test.toml"), CASE).unwrap();
    let file = dir.path().join("cal.toml");
    std::fs::write(
        &file,
        "version = 1\nname = \"glass\"\nreplicates = 2\n[[parameters]]\nkey = \"contact.rolling_friction\"\nmin = 0.0\nmax = 0.2\n\
         [[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.001\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let output = hopperflow(&[
        "calibrate",
        utf8(&file),
        "--out",
        utf8(&out),
        "--slurm",
        "--time",
        "2:00:00",
    ]);
    assert_status(&output, 0, "--slurm without --submit");
    let slurm = out.join("rounds").join("round-01").join("slurm");
    let array = std::fs::read_to_string(slurm.join("array-1.sh")).unwrap();
    // One parameter: five design points, two replicates each.
    assert!(array.contains("--array=0-9"), "{array}");
    assert!(
        array.contains("calibrate") && array.contains("--round 1 --task-list"),
        "{array}"
    );
    let next = std::fs::read_to_string(slurm.join("report.sh")).unwrap();
    assert!(next.contains("--round 1 --collect"), "{next}");
    // The options the next round's jobs are written with.
    let saved = std::fs::read_to_string(out.join("slurm-options.txt")).unwrap();
    assert!(saved.contains("--time=2:00:00"), "{saved}");
}
