//! The calibration loop end to end with a stand-in for the simulation: a test whose measure
//! is a known function of the parameters plus seeded noise, so that the loop's recovery,
//! its records and its resumption are checked in milliseconds. The real round trip, with
//! simulations, is the ignored test in crates/cli/tests/validation.rs and docs/physics.md §12.4.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use calibrate::{
    run_calibration, CalibrationError, CalibrationOptions, CALIBRATION_FILE, RUNS_FILE,
};
use case::{parse_calibration, CalibrationPlan, SweepCase};
use files::{CaseSummary, CASE_FILE};
use study::CaseRunner;

/// A finished run's summary, as a real slab run wrote it; the stand-in changes its rate.
const SUMMARY: &str = include_str!("calibration_summary.json");

/// A small slab case whose friction and rolling friction the calibrations below search.
const CASE: &str = "version = 1\nseed = 3\n[particles]\ncount = 200\n";

/// The stand-in's truth: W = 0.02 + 0.01 μ + 0.004 μ_r² [kg/s] and bulk φ = 0.55 + 0.05 μ_r,
/// each with noise of sd 0.0005 and 0.002 drawn from the run's seed.
fn measures(friction: f64, rolling: f64, seed: u64) -> (f64, f64) {
    // Two standard normal deviates from the seed (splitmix64, Box–Muller): the same seed
    // gives the same noise, as a simulation with the same fill would.
    let mut state = seed;
    let mut uniform = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let (a, b) = (uniform().max(1e-12), uniform());
    let r = (-2.0 * a.ln()).sqrt();
    let (n1, n2) = (
        r * (std::f64::consts::TAU * b).cos(),
        r * (std::f64::consts::TAU * b).sin(),
    );
    (
        0.02 + 0.01 * friction + 0.004 * rolling * rolling + 0.0005 * n1,
        0.55 + 0.05 * rolling + 0.002 * n2,
    )
}

struct Stand {
    calls: AtomicUsize,
    /// Sets this flag and fails from this call on (a kill), when given.
    kill_after: Option<(usize, &'static AtomicBool)>,
    ran: Mutex<Vec<String>>,
}

impl Stand {
    fn new() -> Self {
        Self {
            calls: AtomicUsize::new(0),
            kill_after: None,
            ran: Mutex::new(Vec::new()),
        }
    }
}

impl CaseRunner for Stand {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        let call = self.calls.fetch_add(1, Ordering::SeqCst);
        if let Some((limit, flag)) = self.kill_after {
            if call >= limit {
                flag.store(true, Ordering::SeqCst);
                return Err("killed".into());
            }
        }
        self.ran.lock().unwrap().push(case.id.clone());
        let text = case.case.to_toml_string();
        std::fs::write(dir.join(CASE_FILE), &text).unwrap();
        let friction = case.case.contact.particle.friction;
        let rolling = case.case.contact.particle.rolling_friction;
        let (rate, phi) = measures(friction, rolling, case.case.seed);
        let mut summary: serde_json::Value = serde_json::from_str(SUMMARY).unwrap();
        summary["discharge_rate"] = rate.into();
        summary["bulk_volume_fraction"] = phi.into();
        summary["seed"] = case.case.seed.into();
        // The identity of the run's inputs, as a run records it (SHA-256 of its case text).
        summary["config_hash"] = files::hex_hash(&text).into();
        Ok(serde_json::from_value(summary).unwrap())
    }
}

/// A calibration of μ and μ_r from W and φ whose targets are the stand-in's truth at
/// μ = 0.45, μ_r = 0.3 (W = 0.02486 kg/s, φ = 0.565) with the given uncertainties.
fn plan_in(dir: &Path, extra: &str) -> CalibrationPlan {
    std::fs::write(dir.join("test.toml"), CASE).unwrap();
    let text = format!(
        "version = 1\nname = \"stand\"\nreplicates = 3\n{extra}\n\
         [[parameters]]\nkey = \"contact.friction\"\nmin = 0.1\nmax = 0.9\n\
         [[parameters]]\nkey = \"contact.rolling_friction\"\nmin = 0.0\nmax = 0.6\n\
         [[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.02486\nuncertainty = 0.0002\n\
         [[targets]]\ncase = \"test.toml\"\nmeasure = \"bulk_volume_fraction\"\nvalue = 0.565\nuncertainty = 0.001\n"
    );
    parse_calibration(&text, "stand.toml", Some(dir)).unwrap()
}

fn calibrate(
    plan: &CalibrationPlan,
    out: &Path,
    runner: &Stand,
    stop: Option<&AtomicBool>,
) -> Result<calibrate::CalibrationRecord, CalibrationError> {
    run_calibration(
        plan,
        out,
        runner,
        &CalibrationOptions { jobs: 2 },
        &|_| {},
        stop,
    )
}

#[test]
fn known_parameters_are_recovered_within_their_stated_uncertainty() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_in(dir.path(), "");
    let runner = Stand::new();
    let record = calibrate(&plan, &dir.path().join("out"), &runner, None).unwrap();
    assert!(record.converged && record.targets_met, "{record:#?}");
    for (estimate, truth) in record.estimate.iter().zip([0.45, 0.3]) {
        // 3σ: a miss has probability 0.3 % for an unbiased estimate with a correct error;
        // and the error is informative, under a tenth of the range.
        assert!(
            (estimate.value - truth).abs() < 3.0 * estimate.standard_error
                && estimate.standard_error < 0.06,
            "{estimate:?} against {truth}"
        );
    }
    // Every run is in runs.csv, one line each after the header.
    let runs = std::fs::read_to_string(dir.path().join("out").join(RUNS_FILE)).unwrap();
    assert_eq!(runs.lines().count(), record.runs + 1);
    assert_eq!(record.runs, runner.ran.lock().unwrap().len());
    assert_eq!(record.runs, record.rounds.len() * 9 * 3);
    // Its report states the estimate and draws each target against each parameter.
    let files = report::build_calibration_report(&dir.path().join("out")).unwrap();
    let text = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(
        text.contains("Converged") && text.contains("contact.rolling_friction"),
        "{text}"
    );
    // 2 targets × 2 parameters and the design plane, each as PNG and SVG.
    assert_eq!(files.figures.len(), 2 * (2 * 2 + 1));
}

#[test]
fn a_killed_calibration_continues_to_the_files_of_one_never_stopped() {
    let whole = tempfile::tempdir().unwrap();
    let plan = plan_in(whole.path(), "");
    calibrate(&plan, &whole.path().join("out"), &Stand::new(), None).unwrap();

    let cut = tempfile::tempdir().unwrap();
    let plan = plan_in(cut.path(), "");
    static STOP: AtomicBool = AtomicBool::new(false);
    // Killed in the second round (a round is 27 runs).
    let killed = Stand {
        kill_after: Some((40, &STOP)),
        ..Stand::new()
    };
    let result = calibrate(&plan, &cut.path().join("out"), &killed, Some(&STOP));
    assert!(
        matches!(result, Err(CalibrationError::Stopped)),
        "{result:?}"
    );
    let resumed = Stand::new();
    calibrate(&plan, &cut.path().join("out"), &resumed, None).unwrap();
    // The finished runs were not repeated: the two invocations ran each run once.
    let record: serde_json::Value = serde_json::from_slice(
        &std::fs::read(cut.path().join("out").join(CALIBRATION_FILE)).unwrap(),
    )
    .unwrap();
    assert_eq!(
        killed.ran.lock().unwrap().len() + resumed.ran.lock().unwrap().len(),
        record["runs"].as_u64().unwrap() as usize
    );
    for file in [CALIBRATION_FILE, RUNS_FILE] {
        let a = std::fs::read(whole.path().join("out").join(file)).unwrap();
        let b = std::fs::read(cut.path().join("out").join(file)).unwrap();
        assert!(a == b, "{file} differs after the resumption");
    }
}

#[test]
fn a_folder_of_another_calibration_is_refused_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_in(dir.path(), "max_rounds = 1");
    let out = dir.path().join("out");
    calibrate(&plan, &out, &Stand::new(), None).unwrap();
    let before = std::fs::read(out.join(CALIBRATION_FILE)).unwrap();
    let mut other = plan.clone();
    other.targets[0].value = 0.025;
    let result = calibrate(&other, &out, &Stand::new(), None);
    assert!(
        matches!(result, Err(CalibrationError::DifferentCalibration { .. })),
        "{result:?}"
    );
    assert_eq!(std::fs::read(out.join(CALIBRATION_FILE)).unwrap(), before);
}

#[test]
fn a_measure_no_run_has_is_named_with_those_it_has() {
    let dir = tempfile::tempdir().unwrap();
    let mut plan = plan_in(dir.path(), "max_rounds = 1");
    plan.targets[1].measure = "repose.angle_deg".into();
    let error = calibrate(&plan, &dir.path().join("out"), &Stand::new(), None).unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("repose.angle_deg") && text.contains("bulk_volume_fraction"),
        "{text}"
    );
}

#[test]
fn rounds_run_as_slurm_tasks_give_the_files_of_a_local_calibration() {
    let local = tempfile::tempdir().unwrap();
    let plan = plan_in(local.path(), "");
    calibrate(&plan, &local.path().join("out"), &Stand::new(), None).unwrap();

    // As the jobs do: each round's study prepared, its runs as separate tasks, then the job
    // after the array asks what comes next.
    let cluster = tempfile::tempdir().unwrap();
    let plan = plan_in(cluster.path(), "");
    let out = cluster.path().join("out");
    let runner = Stand::new();
    let mut rounds = 0;
    loop {
        match calibrate::slurm_step(&plan, &out).unwrap() {
            calibrate::SlurmStep::Run(round, sweep) => {
                let dir = calibrate::round_dir(&out, round);
                study::prepare_study(&sweep, &dir).unwrap();
                for case in &sweep.cases {
                    study::run_task(&sweep, &dir, &case.id, &runner).unwrap();
                }
                rounds += 1;
                assert!(rounds <= plan.max_rounds, "the chain does not end");
            }
            calibrate::SlurmStep::Finished(record) => {
                assert_eq!(record.rounds.len(), rounds as usize);
                break;
            }
        }
    }
    for file in [CALIBRATION_FILE, RUNS_FILE] {
        let a = std::fs::read(local.path().join("out").join(file)).unwrap();
        let b = std::fs::read(out.join(file)).unwrap();
        assert!(
            a == b,
            "{file} differs between the local and the task-by-task calibration"
        );
    }
}
