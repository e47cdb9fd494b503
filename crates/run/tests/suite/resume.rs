//! A run interrupted during the fill and again during the discharge, then resumed from its
//! checkpoints, writes byte-identical outputs to an uninterrupted run; so does a run on
//! two threads.

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::tiny_hopper;

use tiny_hopper::read;

use run::{run_case, Progress, RunOptions, RunOutcome};

use files::{CHECKPOINT_FILE, SUMMARY_FILE};

/// Options that record the phase after every protocol chunk.
fn recording_options(
    threads: usize,
    resume: bool,
    chunk_limit: Option<u64>,
) -> (RunOptions, Arc<Mutex<Vec<&'static str>>>) {
    let phases = Arc::new(Mutex::new(Vec::new()));
    let sink = Arc::clone(&phases);
    let options = RunOptions {
        threads,
        resume,
        progress: Some(Arc::new(move |p: &Progress| {
            sink.lock().expect("phase log").push(p.phase)
        })),
        pictures: false,
        chunk_limit,
        stop: None,
        save_bed: None,
    };
    (options, phases)
}

/// Compares the files that depend on the simulated particles byte for byte.
fn assert_same_outputs(a: &Path, b: &Path, what: &str) {
    for name in [
        SUMMARY_FILE,
        "flow.csv",
        "profiles.csv",
        "field.csv",
        "residence.csv",
        "case.toml",
    ] {
        let (left, right) = (read(a, name), read(b, name));
        assert!(
            left == right,
            "{what}: {name} differs:\n--- reference\n{}\n--- other\n{}",
            String::from_utf8_lossy(&left),
            String::from_utf8_lossy(&right)
        );
    }
}

#[test]
fn run_resumed_after_interruptions_in_fill_and_discharge_matches_uninterrupted_run() {
    let case = tiny_hopper::tiny_case(&[]);
    let root = tempfile::tempdir().expect("temporary directory");
    let (a, b, c) = (
        root.path().join("a"),
        root.path().join("b"),
        root.path().join("c"),
    );

    // The uninterrupted reference, recording which phase each chunk ended in.
    let started = Instant::now();
    let (options, phases) = recording_options(1, false, None);
    let outcome = run_case(&case, &a, &options).expect("reference run");
    let reference_seconds = started.elapsed().as_secs_f64();
    let RunOutcome::Finished(summary) = outcome else {
        panic!("the reference run was interrupted")
    };
    let phases = phases.lock().expect("phase log").clone();
    let count = |name: &str| phases.iter().filter(|p| **p == name).count();
    eprintln!(
        "reference: {:.1} s wall, {} chunks (fill {}, settle {}, discharge {}), stop {:?}, W = {:.4} kg/s, discharged {:.3e} kg",
        reference_seconds,
        phases.len(),
        count("fill"),
        count("settle"),
        count("discharge"),
        summary.stop_reason,
        summary.discharge_rate,
        summary.discharged_mass
    );
    // The interruption points only test something if the protocol has those phases to cut.
    assert!(
        count("fill") >= 2,
        "the fill took {} chunks; the tiny case must fill in several batches",
        count("fill")
    );
    assert!(
        count("discharge") >= 4,
        "the discharge took only {} chunks",
        count("discharge")
    );
    // A steady window is needed for profiles.csv and field.csv to hold data worth comparing.
    assert!(
        summary.discharge_rate.is_finite(),
        "the reference run found no steady discharge rate"
    );

    // Chunk k (1-based) of the reference ended in phase phases[k − 1]. Stop once in the
    // middle of the fill and once in the middle of the discharge.
    let first_fill = phases
        .iter()
        .position(|p| *p == "fill")
        .expect("fill chunks") as u64;
    let cut_in_fill = first_fill + (count("fill") as u64).div_ceil(2);
    let first_discharge = phases
        .iter()
        .position(|p| *p == "discharge")
        .expect("discharge chunks") as u64;
    let cut_in_discharge = first_discharge + (count("discharge") as u64) / 2;
    assert_eq!(
        phases[cut_in_fill as usize - 1],
        "fill",
        "first cut is not inside the fill"
    );
    assert_eq!(
        phases[cut_in_discharge as usize - 1],
        "discharge",
        "second cut is not inside the discharge"
    );

    let started = Instant::now();
    let (options, _) = recording_options(1, false, Some(cut_in_fill));
    assert!(matches!(
        run_case(&case, &b, &options).expect("first leg"),
        RunOutcome::Interrupted
    ));
    assert!(
        b.join(CHECKPOINT_FILE).is_file(),
        "an interrupted run left no checkpoint"
    );
    assert!(
        !b.join(SUMMARY_FILE).exists(),
        "an interrupted run wrote a summary"
    );
    // chunk_limit counts the chunks of one call, so the second leg runs the difference.
    let (options, _) = recording_options(1, true, Some(cut_in_discharge - cut_in_fill));
    assert!(matches!(
        run_case(&case, &b, &options).expect("second leg"),
        RunOutcome::Interrupted
    ));
    let (options, leg_phases) = recording_options(1, true, None);
    assert!(matches!(
        run_case(&case, &b, &options).expect("last leg"),
        RunOutcome::Finished(_)
    ));
    // The last leg must have continued the discharge, not restarted the fill.
    let leg_phases = leg_phases.lock().expect("phase log").clone();
    assert_eq!(
        leg_phases.len() as u64,
        phases.len() as u64 - cut_in_discharge,
        "the resumed leg did not pick up where the second stopped"
    );
    assert!(
        !b.join(CHECKPOINT_FILE).exists(),
        "a finished run keeps its checkpoint"
    );
    eprintln!(
        "interrupted twice and resumed: {:.1} s wall",
        started.elapsed().as_secs_f64()
    );
    // Bit-identical resumption (docs/physics.md §10.8): every output byte must match.
    assert_same_outputs(&a, &b, "resumed run");

    let started = Instant::now();
    let (options, _) = recording_options(2, false, None);
    run_case(&case, &c, &options).expect("two-thread run");
    eprintln!("two threads: {:.1} s wall", started.elapsed().as_secs_f64());
    // The engine promises results independent of the thread count.
    assert_same_outputs(&a, &c, "two-thread run");
}
