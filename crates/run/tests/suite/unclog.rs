//! Breaking arches and going on (`[protocol.unclog]`, docs/physics.md §5.11): a clogged
//! tiny hopper is pulsed, flows again, and its avalanches are written; a run killed between
//! its clogs resumes to the same bytes.
//!
//! Whole runs of several seconds each, so ignored by the test command; run them with
//! `cargo test -p hopperflow-run --test suite unclog -- --ignored`.

use std::collections::BTreeMap;
use std::path::PathBuf;

use files::StopReason;
use run::{run_case, CaseRun, Phase, RunOptions, RunOutcome};

use crate::run_dir::{files, table};
use crate::tiny_hopper;

/// The tiny hopper with a 3.2 d outlet, which arches within a tenth of a second, breaking
/// its arches until `avalanches` avalanches have ended in a clog.
fn clogging_case(avalanches: u32) -> case::Case {
    let count = format!("protocol.unclog.avalanches={avalanches}");
    tiny_hopper::tiny_case(&[
        "geometry.outlet_width=0.0095",
        "protocol.time_limit=3.0",
        "protocol.unclog.method=\"air_jet\"",
        count.as_str(),
    ])
}

#[test]
#[ignore = "a whole tiny run that clogs three times: about 5 s; cargo test -p hopperflow-run --test suite unclog -- --ignored"]
fn the_pulse_breaks_the_arch_without_fluidising_the_bed() {
    // The first clog of the tiny hopper, its pulse (25 weights for 10 ms on the grains
    // within D + 2d of the orifice) and the flow after it.
    let case = clogging_case(3);
    let mut run = CaseRun::new(&case, 1).expect("builds");
    let positions = |run: &CaseRun| -> BTreeMap<u64, [f64; 3]> {
        let p = run.simulation().particles();
        (0..p.len())
            .map(|k| (p.tags()[k], p.positions()[k].to_array()))
            .collect()
    };
    let mut before = None;
    let mut pulses = 0;
    loop {
        let was = run.phase();
        run.advance().expect("advances");
        match (was, run.phase()) {
            (Phase::Discharge { .. }, Phase::Pulse { .. }) => before = Some(positions(&run)),
            (Phase::Pulse { .. }, Phase::Discharge { .. }) if pulses == 0 => {
                pulses += 1;
                let after = positions(&run);
                // Grains more than two regions' heights (31 mm) above the outlet moved by
                // less than a diameter: the pulse loosens the bed over the orifice, it does
                // not fluidise the bed (they move about 1 mm in this shallow hopper).
                let d = 0.003;
                let reach = 2.0 * (0.0095 + 2.0 * d);
                for (tag, x) in before.take().expect("a pulse started") {
                    let Some(y) = after.get(&tag) else { continue };
                    if x[2] > reach {
                        let moved = (0..3).map(|i| (y[i] - x[i]).powi(2)).sum::<f64>().sqrt();
                        assert!(moved < d, "grain {tag} at z = {} moved {moved} m", x[2]);
                    }
                }
            }
            (_, Phase::Done { reason, .. }) => {
                // Every clog was broken by its pulses: the run collected its avalanches.
                assert_eq!(reason, StopReason::Avalanches);
                break;
            }
            _ => {}
        }
    }
    assert_eq!(pulses, 1);
}

#[test]
#[ignore = "three whole tiny runs, one killed twice: about 15 s; cargo test -p hopperflow-run --test suite unclog -- --ignored"]
fn avalanches_are_written_and_a_killed_run_resumes_to_the_same_bytes() {
    let case = clogging_case(3);
    let root = tempfile::tempdir().expect("temporary directory");
    let (whole, killed) = (root.path().join("whole"), root.path().join("killed"));
    let summary = match run_case(&case, &whole, &RunOptions::default()).expect("runs") {
        RunOutcome::Finished(s) => *s,
        RunOutcome::Interrupted => panic!("not interrupted"),
    };
    assert_eq!(summary.stop_reason, StopReason::Avalanches);
    let stats = summary.avalanches.expect("an avalanche summary");
    assert_eq!(stats.count, 3);
    // avalanches.csv: the three clog-ended avalanches, each of at least one grain, each
    // with an arch of two grains or more over the 3.2 d slot (its feet on the plates), an
    // arrest before it at least the clog timeout (0.1 s), and its start before its end.
    let rows = table(&whole.join("avalanches.csv"));
    assert_eq!(rows.len(), 3, "{rows:?}");
    let mut total = 0.0;
    for (k, r) in rows.iter().enumerate() {
        let (size, start, end, arrest, grains) = (r[1], r[3], r[4], r[6], r[9]);
        assert!(size >= 1.0 && end >= start, "row {k}: {r:?}");
        assert!(grains >= 2.0, "row {k}: {r:?}");
        if k > 0 {
            assert!(arrest >= 0.1, "row {k}: {r:?}");
        }
        total += size;
    }
    assert!((stats.mean_size - total / 3.0).abs() < 1e-9 * total);
    // Killed twice (after 150 and 300 protocol chunks, in the discharge's pulses and
    // avalanches), resumed each time from its last checkpoint: the same bytes.
    for chunks in [150, 300] {
        let options = RunOptions {
            chunk_limit: Some(chunks),
            ..RunOptions::default()
        };
        let outcome = run_case(&case, &killed, &options).expect("the first chunks run");
        assert!(matches!(outcome, RunOutcome::Interrupted));
    }
    run_case(&case, &killed, &RunOptions::default()).expect("resumes");
    let strip = |dir: &PathBuf| -> BTreeMap<PathBuf, Vec<u8>> {
        files(dir)
            .into_iter()
            .filter(|(p, _)| p.file_name() != Some("timing.json".as_ref()))
            .map(|(p, b)| (p.strip_prefix(dir).expect("inside").to_path_buf(), b))
            .collect()
    };
    let (a, b) = (strip(&whole), strip(&killed));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, bytes) in &a {
        assert!(
            bytes == &b[name],
            "{} differs after the resume",
            name.display()
        );
    }
}
