//! The study runner with a fake simulation: parallel cases, failure isolation, resuming.

use crate::study_fake;

use std::sync::atomic::Ordering;

use case::{parse_sweep, SweepPlan};
use files::{read_results_table, CaseStatus};
use study::{run_study, StudyError, StudyEvent, StudyOptions};
use study_fake::FakeRunner;

/// Six cases: two hopper angles × three outlet widths.
const SMALL_SWEEP: &str = r#"
version = 1
name = "small"
[base]
version = 1
seed = 7
[[axes]]
key = "geometry.hopper_angle_deg"
values = [60.0, 90.0]
label = "a"
[[axes]]
key = "geometry.outlet_width"
values = [0.018, 0.030, 0.045]
label = "D"
scale = 1000.0
digits = 3
"#;

fn small_plan() -> SweepPlan {
    parse_sweep(SMALL_SWEEP, "small", None, &[]).expect("the small sweep must expand")
}

fn quiet(_: &StudyEvent) {}

fn options(jobs: usize) -> StudyOptions {
    StudyOptions { jobs }
}

#[test]
fn parallel_study_runs_every_case_once_and_tabulates_them_sorted() {
    let plan = small_plan();
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        sleep_ms: 30,
        ..FakeRunner::new()
    };
    let outcome = run_study(&plan, dir.path(), &fake, &options(3), &quiet).unwrap();
    assert_eq!(fake.calls.load(Ordering::SeqCst), plan.cases.len());
    assert_eq!(outcome.ran, 6);
    assert_eq!(outcome.reused, 0);
    // With three workers and 30 ms per case, at least two cases must overlap in time.
    assert!(fake.max_active.load(Ordering::SeqCst) >= 2);

    let rows = read_results_table(&dir.path().join("results.csv")).unwrap();
    let ids: Vec<&str> = rows.iter().map(|r| r.id.as_str()).collect();
    let mut sorted = ids.clone();
    sorted.sort();
    assert_eq!(ids, sorted, "rows are sorted by identifier");
    assert_eq!(rows.len(), 6);
    for row in &rows {
        let summary: files::CaseSummary = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("cases").join(&row.id).join("summary.json"))
                .unwrap(),
        )
        .unwrap();
        // The table stores shortest round-trip decimals, so W reads back bit for bit.
        assert_eq!(row.discharge_rate, summary.discharge_rate);
        assert!(row.discharge_rate > 0.0);
        assert_eq!(row.status, CaseStatus::Complete);
        // The fake's flux check is 1.01 W; the table's ratio must show it (to rounding).
        assert!((row.flux_check_ratio - 1.01).abs() < 1e-12);
    }
    assert!(dir.path().join("study.json").exists());
}

#[test]
fn failing_and_panicking_cases_are_reported_and_the_others_finish() {
    let plan = small_plan();
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        fail: vec!["small-a60-D030-r0".into()],
        panic: vec!["small-a90-D018-r0".into()],
        clog: vec!["small-a90-D045-r0".into()],
        ..FakeRunner::new()
    };
    let events = std::sync::Mutex::new(Vec::new());
    let record = |e: &StudyEvent| events.lock().unwrap().push(e.clone());
    let outcome = run_study(&plan, dir.path(), &fake, &options(2), &record).unwrap();
    assert_eq!(fake.calls.load(Ordering::SeqCst), 6, "every case was tried");
    let failed: Vec<&str> = outcome.failures.iter().map(|f| f.id.as_str()).collect();
    assert_eq!(failed, ["small-a60-D030-r0", "small-a90-D018-r0"]);
    assert!(outcome.failures[1].reason.contains("panicked"));

    let rows = read_results_table(&dir.path().join("results.csv")).unwrap();
    let status = |id: &str| rows.iter().find(|r| r.id == id).unwrap().status;
    assert_eq!(status("small-a60-D030-r0"), CaseStatus::Failed);
    assert_eq!(status("small-a90-D018-r0"), CaseStatus::Failed);
    assert_eq!(status("small-a90-D045-r0"), CaseStatus::Clogged);
    assert_eq!(status("small-a60-D018-r0"), CaseStatus::Complete);
    let failed_row = rows.iter().find(|r| r.id == "small-a60-D030-r0").unwrap();
    assert!(failed_row.discharge_rate.is_nan(), "a failed case has no W");
    assert_eq!(
        failed_row.outlet_width, 0.030,
        "its inputs are still listed"
    );

    let failures: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("failures.json")).unwrap())
            .unwrap();
    assert_eq!(failures.as_array().unwrap().len(), 2);

    let events = events.into_inner().unwrap();
    let ended = events
        .iter()
        .filter(|e| matches!(e, StudyEvent::CaseEnded { .. }))
        .count();
    assert_eq!(ended, 6, "one line per finished case");
    let last_done = events.iter().filter_map(|e| match e {
        StudyEvent::CaseEnded { done, .. } => Some(*done),
        _ => None,
    });
    assert_eq!(last_done.max(), Some(6));

    // A restart retries only the two failures; the clogged case counts as finished.
    let retry = FakeRunner::new();
    let outcome = run_study(&plan, dir.path(), &retry, &options(2), &quiet).unwrap();
    assert_eq!(retry.calls.load(Ordering::SeqCst), 2);
    assert!(outcome.failures.is_empty());
}

#[test]
fn killed_study_resumes_without_recomputing_and_gives_the_uninterrupted_table() {
    let plan = small_plan();
    let whole = tempfile::tempdir().unwrap();
    run_study(&plan, whole.path(), &FakeRunner::new(), &options(2), &quiet).unwrap();

    for kill_after in [0, 2, 5] {
        let dir = tempfile::tempdir().unwrap();
        // One worker, so that exactly `kill_after` cases finish before the "kill".
        let killed = FakeRunner {
            stop_after: Some(kill_after),
            ..FakeRunner::new()
        };
        run_study(&plan, dir.path(), &killed, &options(1), &quiet).unwrap();
        let partial = read_results_table(&dir.path().join("results.csv")).unwrap();
        let finished = partial
            .iter()
            .filter(|r| r.status != CaseStatus::Failed)
            .count();
        assert_eq!(finished, kill_after);

        let restart = FakeRunner::new();
        let outcome = run_study(&plan, dir.path(), &restart, &options(2), &quiet).unwrap();
        assert_eq!(
            restart.calls.load(Ordering::SeqCst),
            plan.cases.len() - kill_after,
            "finished cases are not recomputed"
        );
        assert_eq!(outcome.reused, kill_after);
        let ran = restart.ran.lock().unwrap().clone();
        let before: Vec<&str> = partial
            .iter()
            .filter(|r| r.status != CaseStatus::Failed)
            .map(|r| r.id.as_str())
            .collect();
        assert!(ran.iter().all(|id| !before.contains(&id.as_str())));
        assert_eq!(
            std::fs::read_to_string(dir.path().join("results.csv")).unwrap(),
            std::fs::read_to_string(whole.path().join("results.csv")).unwrap(),
            "resumed table equals the uninterrupted one byte for byte"
        );
    }
}

#[test]
fn study_refuses_a_directory_that_holds_another_sweep() {
    let dir = tempfile::tempdir().unwrap();
    run_study(
        &small_plan(),
        dir.path(),
        &FakeRunner::new(),
        &options(1),
        &quiet,
    )
    .unwrap();
    let other = SMALL_SWEEP.replace("seed = 7", "seed = 8");
    let other = parse_sweep(&other, "small", None, &[]).unwrap();
    let fake = FakeRunner::new();
    let error = run_study(&other, dir.path(), &fake, &options(1), &quiet).unwrap_err();
    assert!(
        matches!(error, StudyError::DifferentStudy { .. }),
        "{error}"
    );
    assert_eq!(fake.calls.load(Ordering::SeqCst), 0, "nothing was run");
}

#[test]
fn one_worker_runs_the_smallest_outlets_first() {
    // The expected cost falls with the outlet width, so one worker must take the 18 mm
    // cases, then the 30 mm ones, then the 45 mm ones, whatever the plan's order.
    let plan = small_plan();
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner::new();
    let widths = std::sync::Mutex::new(Vec::new());
    let record = |e: &StudyEvent| {
        if let StudyEvent::CaseEnded { outlet_width, .. } = e {
            widths.lock().unwrap().push(*outlet_width);
        }
    };
    run_study(&plan, dir.path(), &fake, &options(1), &record).unwrap();
    let widths = widths.into_inner().unwrap();
    assert_eq!(widths, vec![0.018, 0.018, 0.030, 0.030, 0.045, 0.045]);
    let costs: Vec<f64> = plan
        .cases
        .iter()
        .map(|c| study::expected_cost(&c.case))
        .collect();
    assert!(costs.iter().all(|c| c.is_finite() && *c > 0.0));
}
