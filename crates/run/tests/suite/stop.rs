//! A run stopped as soon as the steady window is complete (`protocol.stop_fraction` equal to
//! `measure.steady_end_fraction`) measures exactly what a run to the end measures: the same
//! window, W, profiles and field, bit for bit. Only the record of the discharge is shorter.

use std::path::Path;

use run::{run_case, RunOptions, RunOutcome};

use files::SUMMARY_FILE;
use files::{CaseSummary, StopReason};
use tiny_hopper::{read, tiny_case};

use crate::tiny_hopper;

/// The shared tiny hopper (250 spheres, 18 mm outlet), run for up to 1.5 s of discharge.
/// Rate bins of 40 ms hold about 25 spheres each, 10 % of the fill, and spheres are deleted
/// only 2 d below the outlet, so a stop placed by the deleted mass alone leaves the bin that
/// crosses 70 % still open. (Without the protocol's window check this test fails: the short
/// run then stops 7 ms earlier and measures a window cut short, 0.12–0.24 s instead of
/// 0.12–0.32 s.)
fn run(stop: &str, dir: &Path) -> CaseSummary {
    let stop = format!("protocol.stop_fraction={stop}");
    let case = tiny_case(&[
        "seed=5",
        "protocol.time_limit=1.5",
        "protocol.deletion_depth=0.006",
        "measure.rate_bin_width=0.04",
        "output.checkpoint_interval=0.0",
        &stop,
    ]);
    let options = RunOptions {
        pictures: false,
        ..RunOptions::default()
    };
    match run_case(&case, dir, &options).expect("the tiny case runs") {
        RunOutcome::Finished(summary) => *summary,
        RunOutcome::Interrupted => panic!("the run was interrupted"),
    }
}

#[test]
fn stopping_at_the_window_end_measures_what_a_whole_run_measures() {
    let root = tempfile::tempdir().expect("temporary directory");
    let (short, whole) = (root.path().join("short"), root.path().join("whole"));
    let s = run("0.7", &short);
    let w = run("1.0", &whole);
    eprintln!(
        "short: {:?} after {:.3} s, {:.3e} kg; whole: {:?} after {:.3} s, {:.3e} kg; \
         W = {:.5} kg/s over {:?}",
        s.stop_reason,
        s.discharge_time,
        s.discharged_mass,
        w.stop_reason,
        w.discharge_time,
        w.discharged_mass,
        w.discharge_rate,
        w.steady_window
    );

    // The comparison only means something if the short run did stop early, on the fraction.
    assert_eq!(s.stop_reason, StopReason::Fraction);
    assert!(
        s.discharge_time < w.discharge_time,
        "the short run ran {} s, the whole one {} s",
        s.discharge_time,
        w.discharge_time
    );
    assert!(s.discharge_rate.is_finite() && s.discharge_rate > 0.0);

    // Exact equality: both runs follow the same trajectory up to the short run's stop, and
    // everything below is computed from data before it.
    assert_eq!(
        s.steady_window.map(f64::to_bits),
        w.steady_window.map(f64::to_bits),
        "steady window"
    );
    assert_eq!(s.discharge_rate.to_bits(), w.discharge_rate.to_bits(), "W");
    assert_eq!(
        s.discharge_rate_error.to_bits(),
        w.discharge_rate_error.to_bits(),
        "W's standard error"
    );
    assert_eq!(s.plateau_found, w.plateau_found, "plateau");
    for (what, a, b) in [
        ("flux check", s.flux_check_rate, w.flux_check_rate),
        (
            "profile flux check",
            s.flux_check_rate_profiles,
            w.flux_check_rate_profiles,
        ),
        ("v_c", s.centre_velocity, w.centre_velocity),
        ("φ_c", s.centre_area_fraction, w.centre_area_fraction),
    ] {
        // NaN compares by its bits too: both runs must agree on a missing value.
        assert_eq!(a.to_bits(), b.to_bits(), "{what}: {a} against {b}");
    }
    for name in ["profiles.csv", "field.csv"] {
        assert!(
            read(&short, name) == read(&whole, name),
            "{name} differs between the short and the whole run"
        );
    }
    // The summary itself differs (stop reason, discharged mass), which `read` would hide.
    assert!(read(&short, SUMMARY_FILE) != read(&whole, SUMMARY_FILE));
}
