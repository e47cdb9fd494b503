//! A study run as separate tasks, as a scheduler's array job runs it: each task runs one
//! case into its own folder, and a last step collects the folders into the results table.
//!
//! A task writes only inside `cases/<id>/`: the case's outputs, its checkpoint, and on
//! failure [`FAILURE_FILE`]. Tasks of one study therefore never write the same file, and the
//! study-level files (`study.json`, `results.csv`, `failures.json`) are written only by
//! [`prepare_study`] before the tasks and by [`collect_study`] after them. The table that
//! `collect_study` writes is byte-identical to that of the same study run by [`run_study`]:
//! both build each row from the summary as read back from disk.
//!
//! [`run_study`]: super::run_study

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::error::StudyError;
use super::runner::{
    check_study_dir, finished_summary, keep_summary, panic_message, same_study, CaseRunner,
};
use super::simulation::STOPPED;
use case::SweepPlan;
use files::write_json_atomic;
use files::CaseSummary;
use files::{
    write_results_table, CaseFailure, ResultRow, StudyManifest, StudyPaths, CHECKPOINT_FILE,
    FAILURE_FILE,
};

/// How one task ended.
#[derive(Debug, Clone, PartialEq)]
pub enum TaskOutcome {
    /// The case finished (or had finished before); its summary as read back from disk.
    Finished(Box<CaseSummary>),
    /// The case failed; [`FAILURE_FILE`] in its folder holds the reason.
    Failed(String),
    /// A stop was requested (SIGTERM): the case wrote a checkpoint and continues when run
    /// again.
    Stopped,
}

/// Where one case of a study stands, read from its folder.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CaseState {
    /// `summary.json` is there.
    Finished,
    /// Its last task failed, with this reason.
    Failed(String),
    /// Stopped or killed with a checkpoint to continue from.
    Checkpointed,
    /// Started but killed before its first checkpoint.
    Started,
    /// No folder, or an empty one.
    NotStarted,
}

impl CaseState {
    /// Whether a task must still run this case.
    pub fn is_unfinished(&self) -> bool {
        !matches!(self, CaseState::Finished)
    }

    /// A word for tables.
    pub fn label(&self) -> &'static str {
        match self {
            CaseState::Finished => "finished",
            CaseState::Failed(_) => "failed",
            CaseState::Checkpointed => "checkpointed",
            CaseState::Started => "started",
            CaseState::NotStarted => "not started",
        }
    }
}

/// Checks `root` as [`run_study`](super::run_study) does (same sweep, no case folder of other
/// inputs), then writes the manifest and creates `cases/`: what the tasks of `plan` need
/// before they start.
pub fn prepare_study(plan: &SweepPlan, root: &Path) -> Result<(), StudyError> {
    check_study_dir(plan, root)?;
    let paths = StudyPaths::new(root);
    let cases = root.join("cases");
    std::fs::create_dir_all(&cases).map_err(|e| StudyError::io(&cases, e))?;
    super::manifest_of_plan(plan)
        .write(&paths.manifest())
        .map_err(StudyError::from)
}

/// The state of every case of the study in `root`, in the manifest's order. Reads only.
pub fn case_states(root: &Path) -> Result<Vec<(String, CaseState)>, StudyError> {
    let paths = StudyPaths::new(root);
    let manifest = StudyManifest::read(&paths.manifest())?.ok_or_else(|| {
        StudyError::parse(
            paths.manifest(),
            "no study manifest: this folder holds no study",
        )
    })?;
    Ok(manifest
        .cases
        .iter()
        .map(|case| (case.id.clone(), state_of(&paths.case_dir(&case.id))))
        .collect())
}

fn state_of(dir: &Path) -> CaseState {
    if finished_summary(dir).is_some() {
        CaseState::Finished
    } else if let Some(failure) = read_failure(dir) {
        CaseState::Failed(failure.reason)
    } else if dir.join(CHECKPOINT_FILE).is_file() {
        CaseState::Checkpointed
    } else if dir.join(files::CASE_FILE).is_file() {
        CaseState::Started
    } else {
        CaseState::NotStarted
    }
}

fn read_failure(dir: &Path) -> Option<CaseFailure> {
    let text = std::fs::read_to_string(dir.join(FAILURE_FILE)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs case `id` of `plan` into `root/cases/<id>/` with `runner`, writing nothing outside
/// that folder. The study must have been prepared ([`prepare_study`]) with the same plan,
/// and the case's folder must hold nothing of other inputs.
pub fn run_task(
    plan: &SweepPlan,
    root: &Path,
    id: &str,
    runner: &dyn CaseRunner,
) -> Result<TaskOutcome, StudyError> {
    let paths = StudyPaths::new(root);
    let Some(case) = plan.cases.iter().find(|c| c.id == id) else {
        return Err(StudyError::UnknownCase {
            id: id.to_string(),
            known: plan.cases.len(),
        });
    };
    if !same_study(plan, &paths)? {
        return Err(StudyError::parse(
            paths.manifest(),
            "no study manifest; the study must be prepared before its tasks run",
        ));
    }
    let dir = paths.case_dir(id);
    run::check_run_dir(&case.case, &dir).map_err(|source| StudyError::CaseFolder {
        id: id.to_string(),
        source: Box::new(source),
    })?;
    std::fs::create_dir_all(&dir).map_err(|e| StudyError::io(&dir, e))?;
    let result = catch_unwind(AssertUnwindSafe(|| runner.run(case, &dir)))
        .unwrap_or_else(|payload| Err(format!("the run panicked: {}", panic_message(&*payload))))
        .and_then(|summary| keep_summary(&dir, summary));
    let failure_path = dir.join(FAILURE_FILE);
    match result {
        Ok(summary) => {
            remove_if_present(&failure_path)?;
            Ok(TaskOutcome::Finished(Box::new(summary)))
        }
        Err(reason) if reason == STOPPED => Ok(TaskOutcome::Stopped),
        Err(reason) => {
            let failure = CaseFailure {
                id: id.to_string(),
                reason: reason.clone(),
            };
            write_json_atomic(&failure_path, &failure)?;
            Ok(TaskOutcome::Failed(reason))
        }
    }
}

fn remove_if_present(path: &Path) -> Result<(), StudyError> {
    match std::fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(StudyError::io(path, e)),
    }
}

/// What [`collect_study`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Collected {
    /// The rows written to `results.csv`: finished and failed cases, sorted by identifier.
    pub rows: Vec<ResultRow>,
    /// The failed cases, as written to `failures.json`.
    pub failures: Vec<CaseFailure>,
    /// Cases with neither a summary nor a failure (not started, stopped, or still running).
    pub unfinished: Vec<String>,
}

/// Assembles `results.csv` and `failures.json` of `plan` from the case folders in `root`,
/// as [`run_study`](super::run_study) would have written them had it run every finished and
/// failed case itself. Unfinished cases are left out of the table and listed.
pub fn collect_study(plan: &SweepPlan, root: &Path) -> Result<Collected, StudyError> {
    check_study_dir(plan, root)?;
    let paths = StudyPaths::new(root);
    let mut rows = BTreeMap::new();
    let mut failures = BTreeMap::new();
    let mut unfinished = Vec::new();
    for case in &plan.cases {
        let dir = paths.case_dir(&case.id);
        if let Some(summary) = finished_summary(&dir) {
            rows.insert(case.id.clone(), super::measured_row(case, &summary));
        } else if let Some(failure) = read_failure(&dir) {
            rows.insert(case.id.clone(), super::failed_row(case));
            failures.insert(case.id.clone(), failure);
        } else {
            unfinished.push(case.id.clone());
        }
    }
    write_results_table(&paths.results(), &rows)?;
    let failures: Vec<CaseFailure> = failures.into_values().collect();
    write_json_atomic(paths.failures(), &failures)?;
    Ok(Collected {
        rows: rows.into_values().collect(),
        failures,
        unfinished,
    })
}
