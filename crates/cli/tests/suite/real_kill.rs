//! Runs and studies killed with SIGKILL resume to the outputs of an uninterrupted run, byte
//! for byte; a resume under edited inputs is refused and changes nothing; `--restart` gives
//! a fresh run. Everything runs the real binary as a child process.
#![cfg(unix)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use run::read_checkpoint_header;

use files::CHECKPOINT_FILE;

/// A hopper a few particles wide that fills, settles and drains in about a second of wall
/// time: 250 spheres of 3 mm, an 18 mm outlet, a checkpoint every 10 ms of simulated time
/// (so that there are several in each phase to kill after), VTU snapshots and plots on (so
/// that the snapshot series is part of what must resume identically).
const TINY_CASE: &str = concat!(
    include_str!("../../../run/tests/data/tiny.toml"),
    "
[output]
checkpoint_interval = 0.01
vtu_interval = 0.05
plots = true
"
);

/// Upper bound on one phase of the tiny case in wall time; only a hung child reaches it.
const PATIENCE: Duration = Duration::from_secs(120);

/// The tiny case run to its end without interruption, once per test process for every test
/// that compares with it, in a folder of the test build's scratch space named by the process
/// (so that test runners that start a process per test do not share it).
fn reference() -> &'static Path {
    static REFERENCE: OnceLock<PathBuf> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("real_kill-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).expect("the scratch folder");
        let case = root.join("tiny.toml");
        std::fs::write(&case, TINY_CASE).expect("write case");
        let out = root.join("reference");
        let done = run_to_end(&["run", path_str(&case), "--out", path_str(&out), "--quiet"]);
        assert!(
            done.status.success(),
            "reference run: {}",
            String::from_utf8_lossy(&done.stderr)
        );
        out
    })
}

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hopperflow"))
}

fn run_to_end(args: &[&str]) -> Output {
    binary()
        .args(args)
        .output()
        .expect("the hopperflow binary starts")
}

fn spawn(args: &[&str]) -> Child {
    binary()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the hopperflow binary starts")
}

/// Waits until the checkpoint in `dir` was written in `phase` (a successful read means the
/// atomic rename has happened), then SIGKILLs `child`. Returns the phase of the checkpoint
/// left behind, read after the kill.
fn kill_in_phase(mut child: Child, dir: &Path, phase: &str) -> String {
    let started = Instant::now();
    let path = dir.join(CHECKPOINT_FILE);
    loop {
        if let Ok(header) = read_checkpoint_header(&path) {
            if header.phase == phase {
                break;
            }
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("the run ended ({status}) before a checkpoint in the {phase} was seen");
        }
        assert!(
            started.elapsed() < PATIENCE,
            "no checkpoint in the {phase} after {PATIENCE:?}"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().expect("SIGKILL the run");
    let status = child.wait().expect("reap the run");
    assert!(!status.success(), "the run was killed, not finished");
    read_checkpoint_header(&path)
        .expect("a killed run leaves a readable checkpoint: writes are atomic")
        .phase
}

/// Every file under `dir` by relative path, with its bytes; `timing.json` (wall-clock
/// times) left out.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for entry in std::fs::read_dir(dir).expect("read dir") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(root, &path, out);
            } else if path.file_name() != Some("timing.json".as_ref()) {
                let bytes = std::fs::read(&path).expect("read file");
                out.insert(
                    path.strip_prefix(root).expect("inside").to_path_buf(),
                    bytes,
                );
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Asserts that two run directories hold the same files with the same bytes.
fn assert_same_files(reference: &Path, other: &Path, what: &str) {
    let (a, b) = (files(reference), files(other));
    let names = |m: &BTreeMap<PathBuf, Vec<u8>>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(
        names(&a),
        names(&b),
        "{what}: the two runs wrote different files"
    );
    for (name, bytes) in &a {
        assert!(
            bytes == &b[name],
            "{what}: {} differs from the uninterrupted run",
            name.display()
        );
    }
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 temporary path")
}

#[test]
fn run_killed_in_fill_and_discharge_resumes_to_the_uninterrupted_bytes() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case = dir.path().join("tiny.toml");
    std::fs::write(&case, TINY_CASE).expect("write case");
    let (reference, killed) = (reference(), dir.path().join("killed"));
    let case = path_str(&case);

    let first = spawn(&["run", case, "--out", path_str(&killed), "--quiet"]);
    let left = kill_in_phase(first, &killed, "fill");
    // The kill lands a moment after the fill checkpoint was seen; the checkpoint it left is
    // from the fill unless the whole fill ended in that moment.
    assert_eq!(left, "fill", "the first kill did not land in the fill");

    let second = spawn(&[
        "run",
        case,
        "--out",
        path_str(&killed),
        "--resume",
        "--quiet",
    ]);
    kill_in_phase(second, &killed, "discharge");

    let resumed = run_to_end(&[
        "run",
        case,
        "--out",
        path_str(&killed),
        "--resume",
        "--quiet",
    ]);
    assert!(
        resumed.status.success(),
        "resumed run: {}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert!(
        !killed.join(CHECKPOINT_FILE).exists(),
        "a finished run removes its checkpoint"
    );
    assert_same_files(reference, &killed, "killed twice and resumed");
}

#[test]
fn sigterm_checkpoints_exits_75_and_the_resumed_run_matches() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case = dir.path().join("tiny.toml");
    std::fs::write(&case, TINY_CASE).expect("write case");
    let (reference, stopped) = (reference(), dir.path().join("stopped"));
    let case = path_str(&case);

    // SIGTERM (a scheduler's time limit, scancel) once the run is in its settling phase or
    // later: the run writes a checkpoint after its current chunk and exits with 75.
    let child = binary()
        .args(["run", case, "--out", path_str(&stopped), "--quiet"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the hopperflow binary starts");
    let started = Instant::now();
    while !read_checkpoint_header(&stopped.join(CHECKPOINT_FILE))
        .is_ok_and(|h| h.phase == "discharge")
    {
        assert!(started.elapsed() < PATIENCE, "no discharge checkpoint");
        std::thread::sleep(Duration::from_millis(2));
    }
    let seen = read_checkpoint_header(&stopped.join(CHECKPOINT_FILE)).expect("header");
    let term = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(term.success());
    let output = child.wait_with_output().expect("reap");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.code(),
        Some(75),
        "exit status after SIGTERM: {stderr}"
    );
    assert!(stderr.contains("stopped by a signal"), "{stderr}");
    let left = read_checkpoint_header(&stopped.join(CHECKPOINT_FILE)).expect("checkpoint");
    assert!(
        left.time >= seen.time,
        "the checkpoint written on SIGTERM is the latest one ({} s, seen {} s)",
        left.time,
        seen.time
    );
    let resumed = run_to_end(&[
        "run",
        case,
        "--out",
        path_str(&stopped),
        "--resume",
        "--quiet",
    ]);
    assert!(resumed.status.success(), "resume after SIGTERM");
    assert_same_files(reference, &stopped, "stopped by SIGTERM and resumed");
}

#[test]
fn resume_after_an_edit_is_refused_and_restart_equals_a_fresh_run() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case_path = dir.path().join("tiny.toml");
    std::fs::write(&case_path, TINY_CASE).expect("write case");
    let case = path_str(&case_path);
    let (out, fresh) = (dir.path().join("out"), dir.path().join("fresh"));

    let child = spawn(&["run", case, "--out", path_str(&out), "--quiet"]);
    kill_in_phase(child, &out, "fill");

    // The user edits the outlet width, then asks to resume.
    std::fs::write(
        &case_path,
        TINY_CASE.replace("outlet_width = 0.018", "outlet_width = 0.03"),
    )
    .expect("edit case");
    let before = files(&out);
    let refused = run_to_end(&["run", case, "--out", path_str(&out), "--resume", "--quiet"]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(
        refused.status.code(),
        Some(2),
        "exit code; stderr:\n{stderr}"
    );
    assert!(
        stderr.contains("geometry.outlet_width: 0.018 -> 0.03"),
        "the refusal names the key with its old and new values:\n{stderr}"
    );
    assert!(
        stderr.contains("--restart"),
        "the refusal offers --restart:\n{stderr}"
    );
    assert!(before == files(&out), "a refused resume changed the folder");

    // Neither flag: the unfinished run is not silently overwritten either.
    let plain = run_to_end(&["run", case, "--out", path_str(&out), "--quiet"]);
    assert_eq!(
        plain.status.code(),
        Some(2),
        "a plain run over a checkpoint"
    );
    assert!(
        before == files(&out),
        "a refused plain run changed the folder"
    );

    let restarted = run_to_end(&["run", case, "--out", path_str(&out), "--restart", "--quiet"]);
    assert!(
        restarted.status.success(),
        "restart: {}",
        String::from_utf8_lossy(&restarted.stderr)
    );
    let fresh_run = run_to_end(&["run", case, "--out", path_str(&fresh), "--quiet"]);
    assert!(fresh_run.status.success(), "fresh run");
    assert_same_files(&fresh, &out, "--restart after an edit");
}

#[test]
fn damaged_checkpoints_are_refused_with_a_clear_message_and_no_change() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case_path = dir.path().join("tiny.toml");
    std::fs::write(&case_path, TINY_CASE).expect("write case");
    let case = path_str(&case_path);
    let out = dir.path().join("out");
    let child = spawn(&["run", case, "--out", path_str(&out), "--quiet"]);
    kill_in_phase(child, &out, "fill");
    let good = std::fs::read(out.join(CHECKPOINT_FILE)).expect("checkpoint");

    // Another case's checkpoint: the same hopper with another seed.
    let other = dir.path().join("other");
    let other_case = dir.path().join("other.toml");
    std::fs::write(&other_case, TINY_CASE.replace("seed = 11", "seed = 12")).expect("write");
    let child = spawn(&[
        "run",
        path_str(&other_case),
        "--out",
        path_str(&other),
        "--quiet",
    ]);
    kill_in_phase(child, &other, "fill");
    let foreign_case = std::fs::read(other.join(CHECKPOINT_FILE)).expect("checkpoint");

    // Random bytes from a fixed xorshift sequence (no dependency needed for noise).
    let mut x = 0x9e37_79b9_7f4a_7c15u64;
    let random: Vec<u8> = (0..good.len())
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect();
    let mut flipped = good.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10;

    let damaged: [(&str, Vec<u8>, &str); 4] = [
        ("truncated", good[..good.len() / 3].to_vec(), "is truncated"),
        ("flipped bit", flipped, "is corrupt"),
        ("random bytes", random, "is not a hopperflow checkpoint"),
        ("another case's", foreign_case, "seed: 12 -> 11"),
    ];
    for (what, bytes, expected) in damaged {
        std::fs::write(out.join(CHECKPOINT_FILE), &bytes).expect("plant checkpoint");
        let before = files(&out);
        let result = run_to_end(&["run", case, "--out", path_str(&out), "--resume", "--quiet"]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(
            result.status.code(),
            Some(2),
            "{what}: exit code; stderr:\n{stderr}"
        );
        assert!(
            stderr.contains(expected) && stderr.contains("--restart"),
            "{what}: the message says '{expected}' and offers --restart:\n{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{what}: a panic:\n{stderr}");
        assert!(
            before == files(&out),
            "{what}: the refused resume changed the folder"
        );
    }
}

/// A sweep of two tiny cases (outlet widths 18 and 24 mm), checkpointed every 10 ms.
fn tiny_sweep() -> String {
    let base: String = TINY_CASE
        .replace("[geometry]", "[base.geometry]")
        .replace("[particles]", "[base.particles]")
        .replace("[time]", "[base.time]")
        .replace("[protocol]", "[base.protocol]")
        .replace("[output]", "[base.output]")
        .replace("plots = true", "plots = false")
        .replace("vtu_interval = 0.05", "vtu_interval = 0.0")
        .replace("version = 1\nseed = 11", "");
    format!(
        r#"version = 1
name = "tiny-kill"
description = "two tiny cases for the kill test"
replicas = 1

[base]
version = 1
seed = 11
{base}
[[series]]
name = "width"
description = "outlet width"

[[series.axes]]
key = "geometry.outlet_width"
values = [0.018, 0.024]
label = "D"
scale = 1000.0
digits = 3
"#
    )
}

#[test]
fn study_killed_mid_case_continues_that_case_and_writes_the_same_table() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let sweep = dir.path().join("sweep.toml");
    std::fs::write(&sweep, tiny_sweep()).expect("write sweep");
    let sweep = path_str(&sweep);
    let (reference, killed) = (dir.path().join("reference"), dir.path().join("killed"));
    let study = |out: &Path| -> Vec<String> {
        [
            "study",
            sweep,
            "--out",
            path_str(out),
            "--jobs",
            "1",
            "--no-pictures",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let args = study(&reference);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let done = run_to_end(&args);
    assert!(
        done.status.success(),
        "reference study: {}",
        String::from_utf8_lossy(&done.stderr)
    );
    let ids: Vec<String> = std::fs::read_dir(reference.join("cases"))
        .expect("cases")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(ids.len(), 2, "two case folders: {ids:?}");

    // Kill the study while its first case (one job, longest expected first) is discharging.
    let args = study(&killed);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let child = spawn(&args);
    let started = Instant::now();
    let victim = loop {
        let found = ids.iter().find(|id| {
            read_checkpoint_header(&killed.join("cases").join(id).join(CHECKPOINT_FILE))
                .is_ok_and(|h| h.phase == "discharge")
        });
        if let Some(id) = found {
            break id.clone();
        }
        assert!(
            started.elapsed() < PATIENCE,
            "no case reached its discharge"
        );
        std::thread::sleep(Duration::from_millis(2));
    };
    let case_dir = killed.join("cases").join(&victim);
    let mut child = child;
    child.kill().expect("SIGKILL the study");
    child.wait().expect("reap the study");
    assert!(
        !case_dir.join("summary.json").exists(),
        "the killed case had not finished"
    );

    let rerun = run_to_end(&args);
    assert!(
        rerun.status.success(),
        "rerun study: {}",
        String::from_utf8_lossy(&rerun.stderr)
    );
    // The rerun's own wall-clock time by protocol phase: a case continued from a discharge
    // checkpoint spent none of it filling or settling; a recomputed one would have.
    let timing: serde_json::Value =
        serde_json::from_slice(&std::fs::read(case_dir.join("timing.json")).expect("timing.json"))
            .expect("timing.json parses");
    for phase in ["fill", "settle"] {
        assert_eq!(
            timing["protocol_s"][phase].as_f64(),
            Some(0.0),
            "case {victim} was recomputed: the rerun spent time in its {phase}"
        );
    }
    assert!(
        timing["protocol_s"]["discharge"].as_f64() > Some(0.0),
        "the rerun continued the discharge"
    );
    let table = |d: &Path| std::fs::read(d.join("results.csv")).expect("results.csv");
    assert!(
        table(&reference) == table(&killed),
        "results.csv of the killed and rerun study differs from the uninterrupted one"
    );
    for id in &ids {
        for name in [
            "summary.json",
            "flow.csv",
            "profiles.csv",
            "field.csv",
            "case.toml",
        ] {
            let read = |d: &Path| std::fs::read(d.join("cases").join(id).join(name)).ok();
            assert!(
                read(&reference) == read(&killed),
                "case {id}: {name} differs after the kill"
            );
        }
    }
}
