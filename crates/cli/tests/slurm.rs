//! Studies as Slurm array jobs, against real daemons: the quick study submitted as an array
//! gives the `results.csv` of a local run byte for byte; a task cancelled mid-run with
//! `scancel` leaves a checkpoint, and the resubmitted array of the unfinished case gives the
//! same table again; the scripts pass `sbatch --test-only`.
//!
//! These tests need a running cluster and are ignored by a plain `cargo test`. The README's
//! test command (`scripts/test.sh`) starts a one-node cluster on this machine
//! (`scripts/slurm-cluster.sh`), runs them with `--ignored` and `SLURM_CONF` set, and stops
//! the daemons. The checks that need no cluster are in `slurm_input.rs`.
#![cfg(unix)]

#[path = "suite/run_cli.rs"]
mod run_cli;
use run_cli::{hopperflow, utf8};
use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// Longest wait for the queue to drain: the quick study takes seconds of CPU; only a
/// stuck cluster reaches this.
const PATIENCE: Duration = Duration::from_secs(300);

fn text(output: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn cluster_is_configured() {
    assert!(
        std::env::var_os("SLURM_CONF").is_some(),
        "SLURM_CONF is not set: run these tests through scripts/test.sh, which starts a cluster"
    );
}

/// The job ids `--submit` printed: (array, report).
fn job_ids(output: &Output) -> (String, String) {
    let stdout = String::from_utf8_lossy(&output.stdout);
    let find = |label: &str| {
        stdout
            .lines()
            .find_map(|l| l.strip_prefix(label).map(|id| id.trim().to_string()))
            .unwrap_or_else(|| panic!("no '{label}' line:\n{stdout}"))
    };
    (find("submitted array job"), find("submitted report job"))
}

/// Waits until squeue no longer lists any of `jobs` (an array's tasks show as `ID_N` or
/// `ID_[…]`). The whole queue is listed and filtered here: asking squeue for job ids it
/// does not know (yet, or any more) is an error, not an empty list.
fn wait_for(jobs: &[&str]) {
    let started = Instant::now();
    loop {
        let out = Command::new("squeue")
            .args(["--noheader", "--format=%i"])
            .output()
            .expect("squeue runs");
        assert!(out.status.success(), "squeue: {}", text(&out));
        let listed = String::from_utf8_lossy(&out.stdout);
        let ours = listed.lines().any(|line| {
            let line = line.trim();
            jobs.iter()
                .any(|job| line == *job || line.starts_with(&format!("{job}_")))
        });
        if !ours {
            return;
        }
        assert!(
            started.elapsed() < PATIENCE,
            "jobs {jobs:?} still queued after {PATIENCE:?}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// The quick study cut to 300 spheres and its first 40 % of discharge, as
/// `slurm_input.rs` runs it: these tests are about which case runs where, how a cancelled
/// task continues and what is collected, and every case still fills, opens and measures a
/// rate.
const REDUCED: [&str; 3] = [
    "particles.count=300",
    "protocol.stop_fraction=0.4",
    "measure.steady_end_fraction=0.4",
];

/// `hopperflow study fan2023 --quick` reduced as [`REDUCED`] says, into `out`, with `extra`
/// options.
fn reduced_quick(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["study", "fan2023", "--quick", "--no-pictures"];
    for set in REDUCED {
        args.extend(["--set", set]);
    }
    args.extend(["--out", utf8(out)]);
    args.extend_from_slice(extra);
    hopperflow(&args)
}

/// The reduced quick study run here, for the reference table.
fn local_quick(dir: &Path) -> Vec<u8> {
    let out = dir.join("local");
    let run = reduced_quick(&out, &[]);
    assert!(run.status.success(), "local study: {}", text(&run));
    std::fs::read(out.join("results.csv")).expect("local results.csv")
}

#[test]
#[ignore = "needs a Slurm cluster: run through scripts/test.sh"]
fn quick_study_as_an_array_job_gives_the_local_table_and_survives_a_scancel() {
    cluster_is_configured();
    let dir = tempfile::tempdir().expect("temporary directory");
    let reference = local_quick(dir.path());

    // 1. The whole study as an array job, then the report job after it.
    let array = dir.path().join("array");
    let submit = reduced_quick(&array, &["--slurm", "--submit", "--mem", "500M"]);
    assert!(submit.status.success(), "submit: {}", text(&submit));
    let (array_job, report_job) = job_ids(&submit);
    wait_for(&[&array_job, &report_job]);
    let table = std::fs::read(array.join("results.csv")).expect("the report job wrote results.csv");
    assert!(
        table == reference,
        "results.csv of the array job differs from the local run"
    );
    assert!(
        array.join("report/report.md").is_file(),
        "the report job wrote the report"
    );
    let status = hopperflow(&["study", utf8(&array), "--status"]);
    assert!(
        String::from_utf8_lossy(&status.stdout).contains("6 cases: 6 finished"),
        "{}",
        text(&status)
    );

    // 2. One task cancelled while it runs, then the unfinished case resubmitted.
    let cancelled = dir.path().join("cancelled");
    let submit = reduced_quick(
        &cancelled,
        &["--slurm", "--submit", "--mem", "500M", "--throttle", "2"],
    );
    assert!(submit.status.success(), "submit: {}", text(&submit));
    let (array_job, report_job) = job_ids(&submit);
    // With two tasks at a time (the node's two CPUs), task 0 is among the first to run:
    // cancel it once its case has started.
    let first = std::fs::read_to_string(cancelled.join("slurm/tasks-1.txt"))
        .expect("task list")
        .lines()
        .next()
        .expect("a first case")
        .to_string();
    let case_dir = cancelled.join("cases").join(&first);
    let started = Instant::now();
    while !case_dir.join("case.toml").is_file() {
        assert!(started.elapsed() < PATIENCE, "case {first} never started");
        std::thread::sleep(Duration::from_millis(5));
    }
    let cancel = Command::new("scancel")
        .arg(format!("{array_job}_0"))
        .output()
        .expect("scancel runs");
    assert!(cancel.status.success(), "scancel: {}", text(&cancel));
    wait_for(&[&array_job, &report_job]);
    assert!(
        !case_dir.join("summary.json").exists(),
        "the cancelled case finished before the cancel reached it; nothing was tested"
    );
    assert!(
        case_dir.join("checkpoint.bin").is_file(),
        "SIGTERM from scancel must leave a checkpoint"
    );
    let log = std::fs::read_to_string(cancelled.join(format!("slurm/logs/{array_job}_0.out")))
        .unwrap_or_default();
    assert!(
        log.contains("stopped by a signal"),
        "the task says it stopped on the signal:\n{log}"
    );
    // The resubmission runs only the cancelled case, from its checkpoint.
    let resubmit = reduced_quick(&cancelled, &["--slurm", "--submit", "--mem", "500M"]);
    assert!(resubmit.status.success(), "resubmit: {}", text(&resubmit));
    assert!(
        String::from_utf8_lossy(&resubmit.stdout).contains("1 of 6 cases to run"),
        "{}",
        text(&resubmit)
    );
    let (array_job, report_job) = job_ids(&resubmit);
    wait_for(&[&array_job, &report_job]);
    let log = std::fs::read_to_string(cancelled.join(format!("slurm/logs/{array_job}_0.out")))
        .unwrap_or_default();
    assert!(
        log.contains(&format!("{first}: continuing from its checkpoint")),
        "the resubmitted task continued from the checkpoint:\n{log}"
    );
    let table = std::fs::read(cancelled.join("results.csv")).expect("results.csv");
    assert!(
        table == reference,
        "results.csv after scancel and resubmission differs from the local run"
    );
}

#[test]
#[ignore = "needs a Slurm cluster: run through scripts/test.sh"]
fn paper_study_scripts_pass_sbatch_test_only_and_unknown_partitions_are_refused() {
    cluster_is_configured();
    let dir = tempfile::tempdir().expect("temporary directory");
    let out = dir.path().join("fan2023");
    let write = hopperflow(&[
        "study",
        "fan2023",
        "--out",
        utf8(&out),
        "--slurm",
        "--mem",
        "500M",
    ]);
    assert!(write.status.success(), "write: {}", text(&write));
    for script in ["slurm/array-1.sh", "slurm/report.sh"] {
        let check = Command::new("sbatch")
            .args(["--test-only", utf8(&out.join(script))])
            .output()
            .expect("sbatch runs");
        assert!(
            check.status.success(),
            "sbatch --test-only {script}: {}",
            text(&check)
        );
    }
    let tasks = std::fs::read_to_string(out.join("slurm/tasks-1.txt")).expect("task list");
    assert_eq!(
        tasks.lines().count(),
        44,
        "one task per case of the paper's study"
    );

    let refused = dir.path().join("refused");
    let bad = hopperflow(&[
        "study",
        "fan2023",
        "--quick",
        "--out",
        utf8(&refused),
        "--slurm",
        "--partition",
        "nosuchpartition",
    ]);
    assert_eq!(bad.status.code(), Some(2), "{}", text(&bad));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("--partition 'nosuchpartition'") && stderr.contains("debug"),
        "names the partition and the known ones: {stderr}"
    );
    assert!(!refused.exists(), "nothing written for a refused partition");
}
