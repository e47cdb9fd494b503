//! A run's `timing.json` says where its wall time went: by phase of the protocol (fill,
//! settle, discharge) and by phase of the engine's step (forces, integration, lists); and,
//! for a run resumed from a checkpoint, what the whole run cost over all its processes.

use std::path::Path;

use files::CHECKPOINT_FILE;
use run::{run_case, RunOptions, RunOutcome};
use sha2::{Digest, Sha256};
use tiny_hopper::{read, tiny_case};

use crate::tiny_hopper;

#[test]
fn timing_splits_the_run_by_protocol_phase_and_by_engine_phase() {
    let dir = std::env::temp_dir().join(format!("hopperflow-run-timing-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let case = tiny_case(&["output.checkpoint_interval=0.0"]);
    let options = RunOptions {
        pictures: false,
        ..RunOptions::default()
    };
    let outcome = run_case(&case, &dir, &options).expect("the tiny case runs");
    assert!(matches!(outcome, RunOutcome::Finished(_)));
    let timing: serde_json::Value =
        serde_json::from_slice(&read(&dir, "timing.json")).expect("timing.json is JSON");
    let get = |path: &[&str]| -> f64 {
        let mut v = &timing;
        for key in path {
            v = &v[*key];
        }
        v.as_f64()
            .unwrap_or_else(|| panic!("timing.json lacks {path:?}: {timing}"))
    };
    let wall = get(&["wall_time_s"]);
    let (fill, settle, discharge) = (
        get(&["protocol_s", "fill"]),
        get(&["protocol_s", "settle"]),
        get(&["protocol_s", "discharge"]),
    );
    let (forces, integrate, neighbour) = (
        get(&["engine_s", "forces"]),
        get(&["engine_s", "integrate"]),
        get(&["engine_s", "neighbour"]),
    );
    // The tiny case goes through every phase, and every phase takes steps.
    assert!(fill > 0.0 && settle > 0.0 && discharge > 0.0, "{timing}");
    assert!(
        forces > 0.0 && integrate > 0.0 && neighbour > 0.0,
        "{timing}"
    );
    // Nested intervals of one monotonic clock: the engine's phases lie inside the protocol's
    // chunks, and those inside the run; none may be counted twice.
    let protocol = fill + settle + discharge;
    assert!(forces + integrate + neighbour <= protocol, "{timing}");
    assert!(protocol <= wall, "{timing}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `timing.json` of the run in `dir`, and a reader of its numbers by key path.
fn timing(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&read(dir, "timing.json")).expect("timing.json is JSON")
}

fn number(timing: &serde_json::Value, path: &[&str]) -> f64 {
    let mut v = timing;
    for key in path {
        v = &v[*key];
    }
    v.as_f64()
        .unwrap_or_else(|| panic!("timing.json lacks {path:?}: {timing}"))
}

/// Runs the tiny case into `dir` for `chunks` chunks (then it is interrupted with a
/// checkpoint), or to its end.
fn run(dir: &Path, chunks: Option<u64>) -> RunOutcome {
    let case = tiny_case(&[]);
    let options = RunOptions {
        pictures: false,
        chunk_limit: chunks,
        ..RunOptions::default()
    };
    run_case(&case, dir, &options).expect("the tiny case runs")
}

#[test]
fn a_resumed_run_counts_the_time_of_every_process() {
    let dir = std::env::temp_dir().join(format!("hopperflow-run-timing-r-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // The first process stops in the discharge, after its fill and settling; the second
    // takes it up from that checkpoint.
    let mut chunks = 0;
    loop {
        chunks += 40;
        let _ = std::fs::remove_dir_all(&dir);
        assert!(matches!(run(&dir, Some(chunks)), RunOutcome::Interrupted));
        let header = run::read_checkpoint_header(&dir.join(CHECKPOINT_FILE))
            .expect("the interrupted run left a checkpoint");
        if header.phase == "discharge" {
            break;
        }
        assert!(chunks < 4000, "the tiny case never reached its discharge");
    }
    assert!(matches!(run(&dir, None), RunOutcome::Finished(_)));
    let t = timing(&dir);
    // This process took the run up in the discharge: none of its own time filled or settled,
    // while the whole run's did (the first process's share, kept in the checkpoint).
    assert_eq!(number(&t, &["protocol_s", "fill"]), 0.0, "{t}");
    assert!(number(&t, &["resumed_at_s"]) > 0.0, "{t}");
    assert!(number(&t, &["run", "protocol_s", "fill"]) > 0.0, "{t}");
    assert!(number(&t, &["run", "protocol_s", "settle"]) > 0.0, "{t}");
    assert_eq!(number(&t, &["run", "processes"]), 2.0, "{t}");
    assert_eq!(t["run"]["partial"], serde_json::json!(false), "{t}");
    // The whole includes this process's part, and more (the first process's).
    let (own, whole) = (
        number(&t, &["wall_time_s"]),
        number(&t, &["run", "wall_time_s"]),
    );
    assert!(whole > own, "{t}");
    let phases = ["fill", "settle", "discharge"]
        .iter()
        .map(|p| number(&t, &["run", "protocol_s", p]))
        .sum::<f64>();
    assert!(phases <= whole, "{t}");

    // A run that was never interrupted: one process, the whole is its own.
    let _ = std::fs::remove_dir_all(&dir);
    assert!(matches!(run(&dir, None), RunOutcome::Finished(_)));
    let t = timing(&dir);
    assert_eq!(number(&t, &["run", "processes"]), 1.0, "{t}");
    assert_eq!(
        number(&t, &["run", "wall_time_s"]),
        number(&t, &["wall_time_s"]),
        "{t}"
    );
    assert!(t["resumed_at_s"].is_null(), "{t}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_checkpoint_without_the_time_spent_still_resumes_and_says_the_total_is_partial() {
    let dir = std::env::temp_dir().join(format!("hopperflow-run-timing-p-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(matches!(run(&dir, Some(30)), RunOutcome::Interrupted));
    // Rewrite the checkpoint as a build before the record wrote it: the same frame (magic,
    // body length, body, SHA-256 of the body) with the body's trailing time record removed.
    // That record is postcard: three f64 of the protocol and one of the wall (8 bytes each),
    // the process count (one varint byte below 128) and the partial flag (one byte).
    let path = dir.join(CHECKPOINT_FILE);
    let bytes = std::fs::read(&path).expect("checkpoint");
    let body = &bytes[16..bytes.len() - 32];
    let record = 4 * 8 + 1 + 1;
    let body = &body[..body.len() - record];
    let mut old = bytes[..8].to_vec();
    old.extend_from_slice(&(body.len() as u64).to_le_bytes());
    old.extend_from_slice(body);
    old.extend_from_slice(&Sha256::digest(body));
    std::fs::write(&path, &old).expect("rewrite the checkpoint");

    assert!(matches!(run(&dir, None), RunOutcome::Finished(_)));
    let t = timing(&dir);
    assert_eq!(t["run"]["partial"], serde_json::json!(true), "{t}");
    assert_eq!(number(&t, &["run", "processes"]), 1.0, "{t}");
    assert_eq!(
        number(&t, &["run", "wall_time_s"]),
        number(&t, &["wall_time_s"]),
        "{t}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
