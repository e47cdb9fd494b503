//! The `hopperflow` binary's exit statuses, each produced by running it: 0 for a passing
//! verification suite (whose `--json` output is a table of rows), 1 for a study whose output
//! directory cannot be written, 2 for a finished run folder given to `run` and for a folder
//! without a study given to `report`, and 3 for a study in which a case failed. Each refusal
//! must name the folder and leave it as it was.

use crate::run_cli;
use run_cli::{assert_status, hopperflow, stderr_of, utf8};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Exit statuses the command line documents (main.rs, run_cmd.rs, study_cmd.rs,
/// report_cmd.rs, verify_cmd.rs and docs/user-guide.md).
const EXIT_OK: i32 = 0;
const EXIT_FAILED: i32 = 1;
const EXIT_BAD_INPUT: i32 = 2;
const EXIT_CASE_FAILED: i32 = 3;

/// Every file under `dir` with its bytes and modification time, to show that a refused
/// command left the folder exactly as it was.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (Vec<u8>, SystemTime)> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("readable folder") {
            let path = entry.expect("a folder entry").path();
            let meta = std::fs::metadata(&path).expect("metadata");
            if meta.is_dir() {
                files.insert(path.clone(), (Vec::new(), meta.modified().expect("mtime")));
                stack.push(path);
            } else {
                let bytes = std::fs::read(&path).expect("readable file");
                files.insert(path, (bytes, meta.modified().expect("mtime")));
            }
        }
    }
    files
}

#[test]
fn verify_passes_with_status_zero_and_its_json_is_the_table_of_rows() {
    // `--fast` is the resolution `cargo test` runs the suite at (crates/verify), where every
    // row passes; the full resolution takes minutes. The JSON must be the table itself: an
    // array of rows with the six documented keys, every one passing (status 0 means that),
    // covering every case of docs/physics.md §9.
    let output = hopperflow(&["verify", "--fast", "--json"]);
    assert_status(&output, EXIT_OK, "verify --fast --json");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let rows: serde_json::Value =
        serde_json::from_str(&stdout).expect("verify --json prints JSON and nothing else");
    let rows = rows.as_array().expect("an array of rows");
    for row in rows {
        let row = row.as_object().expect("each row is an object");
        let mut keys: Vec<&str> = row.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "expected",
                "measured",
                "pass",
                "quantity",
                "test",
                "tolerance"
            ],
            "exactly the six documented keys"
        );
        assert_eq!(row["pass"], serde_json::Value::Bool(true), "{row:?}");
    }
    for case in [
        "CO1", "CO2", "CO3", "CO4", "CO5", "CO-T", "P1", "A1", "A2", "A3", "A4",
    ] {
        assert!(
            rows.iter().any(|r| r["test"] == case),
            "no row of case {case} in the JSON"
        );
    }
    // Status 1 for a failing row is tested on the mapping itself, in src/verify_cmd.rs:
    // no row of the real suite can be made to fail from outside without a flag that would
    // exist only for that test.
}

/// A one-case sweep: series `blocked`, one outlet width of 30 mm labelled `D` in mm, so
/// its only case is `blocked-D030-r0` (`<series>-<label><value × scale>-r<replica>`, as in
/// the built-in sweeps' `angle-a90-D030-r0`). The case is small and short, so that even if
/// it did run the test would fail in seconds, not hang.
const ONE_CASE_SWEEP: &str = r#"
version = 1
name = "exit-codes"
description = "one small case for the exit-status tests"
replicas = 1

[base]
version = 1
seed = 7

[base.geometry]
width = 0.06
height = 0.15
thickness = 0.00303
outlet_width = 0.03
hopper_angle_deg = 90.0

[base.particles]
count = 50
diameter = 0.003

[base.protocol]
max_settle_time = 0.05
time_limit = 0.05

[base.output]
checkpoint_interval = 0.0
vtu_interval = 0.0

[[series]]
name = "blocked"
description = "its one case cannot get a directory"

[[series.axes]]
key = "geometry.outlet_width"
values = [0.030]
label = "D"
scale = 1000.0
digits = 3
"#;
const ONE_CASE_ID: &str = "blocked-D030-r0";

#[test]
fn a_study_with_a_failed_case_exits_with_three_and_lists_it() {
    // A regular file where the case's directory must go: the case fails at once, before
    // any simulation, through the same path as any failing case (an error from the run
    // becomes a `failed` row and an entry of failures.json). Which error fails the case
    // does not matter to the exit status; this one is fast and certain.
    let scratch = tempfile::tempdir().expect("temporary directory");
    let sweep = scratch.path().join("sweep.toml");
    std::fs::write(&sweep, ONE_CASE_SWEEP).expect("sweep written");
    let out = scratch.path().join("study");
    std::fs::create_dir_all(out.join("cases")).expect("cases folder");
    std::fs::write(out.join("cases").join(ONE_CASE_ID), b"not a folder").expect("blocker");

    let output = hopperflow(&[
        "study",
        utf8(&sweep),
        "--out",
        utf8(&out),
        "--jobs",
        "1",
        "--no-pictures",
    ]);
    assert_status(&output, EXIT_CASE_FAILED, "study with a failing case");
    let stderr = stderr_of(&output);
    let failures = out.join("failures.json");
    assert!(
        stderr.contains("1 case(s) failed") && stderr.contains(utf8(&failures)),
        "stderr must count the failures and say where they are listed:\n{stderr}"
    );
    let listed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&failures).expect("failures.json"))
            .expect("failures.json parses");
    let listed = listed.as_array().expect("an array of failures");
    assert_eq!(listed.len(), 1, "{listed:?}");
    assert_eq!(listed[0]["id"], ONE_CASE_ID);
    let reason = listed[0]["reason"].as_str().expect("a reason");
    assert!(
        reason.contains(ONE_CASE_ID),
        "the reason must name the case's directory: {reason}"
    );
    // The results table keeps the case, marked failed.
    let mut reader = csv::Reader::from_path(out.join("results.csv")).expect("results.csv");
    let headers = reader.headers().expect("headers").clone();
    let column = |name: &str| headers.iter().position(|h| h == name).expect(name);
    let (id, status) = (column("id"), column("status"));
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("a row")).collect();
    assert_eq!(rows.len(), 1);
    assert_eq!((&rows[0][id], &rows[0][status]), (ONE_CASE_ID, "failed"));
    // The report of what finished is written all the same (here: nothing measured).
    let comparison = out.join("report/comparison.json");
    assert!(
        comparison.is_file(),
        "a study with a failed case still writes its report"
    );
    let report = std::fs::read_to_string(out.join("report/report.md")).expect("report.md");
    assert!(report.contains("1 failed"), "the report counts the failure");
}

#[test]
fn a_study_with_no_report_leaves_no_report_folder() {
    // The same failing one-case study (fast), with --no-report: exit 3 for the failure,
    // and no report/ folder.
    let scratch = tempfile::tempdir().expect("temporary directory");
    let sweep = scratch.path().join("sweep.toml");
    std::fs::write(&sweep, ONE_CASE_SWEEP).expect("sweep written");
    let out = scratch.path().join("study");
    std::fs::create_dir_all(out.join("cases")).expect("cases folder");
    std::fs::write(out.join("cases").join(ONE_CASE_ID), b"not a folder").expect("blocker");
    let output = hopperflow(&[
        "study",
        utf8(&sweep),
        "--out",
        utf8(&out),
        "--jobs",
        "1",
        "--no-pictures",
        "--no-report",
    ]);
    assert_status(&output, EXIT_CASE_FAILED, "study with --no-report");
    assert!(out.join("results.csv").is_file());
    assert!(
        !out.join("report").exists(),
        "--no-report must not write the report"
    );
}

#[test]
fn a_study_whose_output_cannot_be_created_exits_with_one() {
    // `--out` names an existing regular file: the study cannot create its folder there.
    // That is a failure of the environment, not of the sweep (which is valid), so the
    // status is the generic 1, the message names the path, and the file is not touched.
    let scratch = tempfile::tempdir().expect("temporary directory");
    let sweep = scratch.path().join("sweep.toml");
    std::fs::write(&sweep, ONE_CASE_SWEEP).expect("sweep written");
    let out = scratch.path().join("taken");
    std::fs::write(&out, b"a file, not a folder").expect("file written");
    let before = snapshot(scratch.path());

    let output = hopperflow(&["study", utf8(&sweep), "--out", utf8(&out)]);
    assert_status(&output, EXIT_FAILED, "study into a file");
    let stderr = stderr_of(&output);
    assert!(
        stderr.contains("cannot create") && stderr.contains(utf8(&out)),
        "stderr must name the folder it cannot create:\n{stderr}"
    );
    assert_eq!(snapshot(scratch.path()), before, "nothing may change");
}

#[test]
fn run_refuses_a_finished_folder_and_leaves_it_untouched() {
    // A folder with summary.json is a finished run (the run writes it last). Running into
    // it again without --resume would overwrite its results, so `run` must refuse with the
    // bad-input status before it writes anything, naming the folder and the way out.
    let scratch = tempfile::tempdir().expect("temporary directory");
    let out = scratch.path().join("finished");
    std::fs::create_dir_all(out.join("frames")).expect("run folder");
    std::fs::write(out.join("summary.json"), br#"{"discharge_rate": 0.042}"#).expect("summary");
    std::fs::write(out.join("timeseries.csv"), b"t,mass\n0,0\n").expect("series");
    std::fs::write(out.join("frames").join("0000.png"), b"\x89PNG").expect("frame");
    let before = snapshot(scratch.path());

    let output = hopperflow(&["run", "--out", utf8(&out), "--quiet"]);
    assert_status(&output, EXIT_BAD_INPUT, "run into a finished folder");
    let stderr = stderr_of(&output);
    assert!(
        stderr.contains(utf8(&out)) && stderr.contains("--resume"),
        "stderr must name the folder and the way out:\n{stderr}"
    );
    assert_eq!(
        snapshot(scratch.path()),
        before,
        "the finished folder must keep its files, bytes and times"
    );
}

#[test]
fn report_refuses_a_folder_that_holds_no_study() {
    // An empty folder (no results.csv) and a folder that does not exist: both are bad
    // input, refused with status 2 and a message naming the folder, and neither may get a
    // report/ folder (or be created).
    let scratch = tempfile::tempdir().expect("temporary directory");
    let empty = scratch.path().join("empty");
    std::fs::create_dir(&empty).expect("empty folder");
    let missing = scratch.path().join("missing");
    let before = snapshot(scratch.path());
    for dir in [&empty, &missing] {
        let output = hopperflow(&["report", utf8(dir)]);
        assert_status(
            &output,
            EXIT_BAD_INPUT,
            &format!("report {}", dir.display()),
        );
        let stderr = stderr_of(&output);
        assert!(
            stderr.contains(&format!("{} holds no study", dir.display()))
                && stderr.contains("results.csv"),
            "stderr must name the folder and what it lacks:\n{stderr}"
        );
    }
    assert_eq!(snapshot(scratch.path()), before, "nothing may be written");
}

#[cfg(unix)]
#[test]
fn output_into_a_closed_pipe_ends_quietly_not_in_a_panic() {
    // `hopperflow init | head -0`: the reader is gone before anything is written. Like any
    // command-line tool, hopperflow ends on SIGPIPE, silently, instead of panicking on the
    // failed print (which printed a backtrace and exited with 101).
    use std::os::unix::process::ExitStatusExt;
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_hopperflow"))
        .arg("init")
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("the hopperflow binary starts");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.signal(),
        Some(13),
        "ended by SIGPIPE: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_run_that_could_not_finish_is_refused_with_status_two_and_writes_nothing() {
    // Δt = 1e-12 s with a discharge of up to 10^9 s: 10^21 steps at most, and likely the base
    // case's 3000 spheres drain in 3.5 s of simulated time, 3.5·10^12 steps: years at any
    // speed. The refusal must name both keys with their values and leave no output folder.
    let tmp = tempfile::tempdir().expect("temporary folder");
    let out = tmp.path().join("run");
    let args = [
        "run",
        "--set",
        "time.time_step=1e-12",
        "--set",
        "protocol.time_limit=1e9",
        "--quiet",
        "--out",
        utf8(&out),
    ];
    let output = hopperflow(&args);
    assert_status(&output, EXIT_BAD_INPUT, "run of 10^21 steps");
    let stderr = stderr_of(&output);
    for fragment in [
        "could not finish",
        "time.time_step = 1e-12 s",
        "protocol.time_limit = 1000000000 s",
        "--no-cost-check",
    ] {
        assert!(stderr.contains(fragment), "{fragment:?} not in {stderr}");
    }
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    // `--estimate` prints the same verdict without running: JSON with the refusal, status 2.
    let output = hopperflow(&[&args[..6], &["--estimate", "--json"]].concat());
    assert_status(&output, EXIT_BAD_INPUT, "run --estimate of 10^21 steps");
    let json: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("--estimate --json prints JSON");
    assert!(json["refusal"].as_str().is_some(), "{json}");
    assert!(json["steps"].as_f64().is_some_and(|s| s > 1e20), "{json}");
    // The likely wall time, which the refusal checks, is over the 30 days too.
    let likely = json["likely_wall_time_total_s"].as_f64();
    assert!(likely.is_some_and(|s| s > 30.0 * 86_400.0), "{json}");
    assert!(!out.exists());
}
