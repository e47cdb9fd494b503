//! A real (tiny) study killed part-way and restarted gives the same results table as one
//! run without interruption, and recomputes no finished case.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use case::{parse_sweep, SweepCase};
use files::CaseSummary;
use run::{run_case, RunOptions, RunOutcome};
use study::{run_study, CaseRunner, SimulationRunner, StudyEvent, StudyOptions};

/// Two cases of 150 spheres in a 45 mm wide, flat-bottomed hopper, outlet 15 and 18 mm
/// (5 and 6 d), stopped after 80 % of the mass or 1 s of discharge.
const TINY_SWEEP: &str = r#"
version = 1
name = "tiny"
[base]
version = 1
seed = 11
[base.geometry]
width = 0.045
height = 0.1
outlet_width = 0.015
hopper_angle_deg = 90.0
[base.particles]
count = 150
[base.protocol]
max_settle_time = 0.4
time_limit = 1.0
stop_fraction = 0.8
[base.output]
checkpoint_interval = 0.05
plots = false
[[axes]]
key = "geometry.outlet_width"
values = [0.015, 0.018]
label = "D"
scale = 1000.0
digits = 3
"#;

fn quiet(_: &StudyEvent) {}

/// Runs the real simulation, but a process "killed" after `finished` cases: the next case
/// stops after a few protocol chunks (leaving its checkpoint), later ones never start.
struct KilledRunner {
    finished: usize,
    calls: AtomicUsize,
}

impl CaseRunner for KilledRunner {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        let call = self.calls.fetch_add(1, Ordering::SeqCst);
        if call > self.finished {
            return Err("killed".into());
        }
        let options = RunOptions {
            chunk_limit: (call == self.finished).then_some(3),
            ..RunOptions::default()
        };
        match run_case(&case.case, dir, &options).map_err(|e| e.to_string())? {
            RunOutcome::Finished(summary) => Ok(*summary),
            RunOutcome::Interrupted => Err("killed mid-case".into()),
        }
    }
}

/// Counts the cases the real runner is asked to run.
struct CountingRunner {
    inner: SimulationRunner,
    calls: AtomicUsize,
}

impl CaseRunner for CountingRunner {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        self.calls.fetch_add(1, Ordering::SeqCst);
        self.inner.run(case, dir)
    }
}

#[test]
fn study_resume_matches_uninterrupted() {
    let plan = parse_sweep(TINY_SWEEP, "tiny", None, &[]).expect("the tiny sweep must expand");
    assert_eq!(plan.cases.len(), 2);
    let runner = || CountingRunner {
        inner: SimulationRunner {
            pictures: false,
            ..Default::default()
        },
        calls: AtomicUsize::new(0),
    };
    let options = StudyOptions { jobs: 2 };

    let whole = tempfile::tempdir().unwrap();
    run_study(&plan, whole.path(), &runner(), &options, &quiet).unwrap();

    let resumed = tempfile::tempdir().unwrap();
    let killed = KilledRunner {
        finished: 1,
        calls: AtomicUsize::new(0),
    };
    // One worker, so the first case finishes and the second is interrupted.
    run_study(
        &plan,
        resumed.path(),
        &killed,
        &StudyOptions { jobs: 1 },
        &quiet,
    )
    .unwrap();
    let unfinished = plan
        .cases
        .iter()
        .filter(|c| {
            !resumed
                .path()
                .join("cases")
                .join(&c.id)
                .join("summary.json")
                .exists()
        })
        .count();
    assert_eq!(unfinished, 1, "the kill left one case unfinished");
    let restart = runner();
    let outcome = run_study(&plan, resumed.path(), &restart, &options, &quiet).unwrap();
    assert_eq!(
        outcome.reused, 1,
        "the finished case is read back, not rerun"
    );
    assert_eq!(restart.calls.load(Ordering::SeqCst), 1);
    assert_eq!(
        std::fs::read_to_string(resumed.path().join("results.csv")).unwrap(),
        std::fs::read_to_string(whole.path().join("results.csv")).unwrap(),
        "a killed and resumed study gives the uninterrupted table"
    );
    // Both cases measured a discharge (not failed), so the comparison is of real rows.
    let rows = files::read_results_table(&whole.path().join("results.csv")).unwrap();
    assert!(rows
        .iter()
        .all(|r| r.status != files::CaseStatus::Failed && r.discharge_rate > 0.0));
}
