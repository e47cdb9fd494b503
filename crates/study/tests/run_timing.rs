//! A run's `timing.json` says where its wall time went: by phase of the protocol (fill,
//! settle, discharge) and by phase of the engine's step (forces, integration, lists).

use study::run::{run_case, RunOptions, RunOutcome};
use tiny_hopper::{read, tiny_case};

mod tiny_hopper;

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
