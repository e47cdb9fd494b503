//! Runs every case of a sweep in parallel, resumably, isolating failures.
//!
//! Layout of a study directory:
//! - `study.json`: the manifest (sweep, version, config hash, seeds);
//! - `cases/<id>/`: one directory per case, filled by the case runner;
//! - `results.csv`: one row per finished case, rewritten atomically after each case;
//! - `failures.json`: the cases that failed in the latest run, with their errors.
//!
//! A case counts as finished when `cases/<id>/summary.json` exists (it is written last and
//! atomically), so a restarted study skips it and reads its row back from that file.

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use super::error::StudyError;
use case::{SweepCase, SweepPlan};
use files::write_json_atomic;
use files::CaseSummary;
use files::{
    write_results_table, CaseFailure, CaseStatus, ResultRow, StudyManifest, StudyPaths,
    SUMMARY_FILE,
};

/// Runs one case into its directory and returns its summary.
///
/// The study writes `summary.json` from the returned value when the runner did not, so a
/// runner may leave that to the study. An `Err` (or a panic) marks the case failed without
/// stopping the others; the case is tried again when the study is restarted.
pub trait CaseRunner: Sync {
    /// Runs `case` with `dir` (already created) as its output directory.
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String>;
}

/// A case's expected cost, for scheduling only (arbitrary units): the number of
/// particles times the time they take to drain, N / W, with the Beverloo rate
/// W ∝ (D − 1.5 d)^{3/2} of a slot (or a rectangle), or (D − 1.5 d)^{5/2} of a circular or square
/// orifice. In the paper's study the 11 cases with D = 18 mm take
/// 2–5 min each and those with D = 60 mm under one; they now start first.
pub fn expected_cost(case: &case::Case) -> f64 {
    let d = case.particles.mean_diameter();
    // Outlets of 1.5 d or less clog at once; keep the estimate finite and large.
    let opening = (case.geometry.outlet_size() - 1.5 * d).max(0.1 * d);
    let n = case.particles.count as f64;
    use case::{CuboidOutlet, Geometry, MeshOutlet};
    let exponent = match &case.geometry {
        Geometry::Slab(_) => 1.5,
        Geometry::Cylinder(_) => 2.5,
        Geometry::Cuboid(g) if g.outlet == CuboidOutlet::Slot => 1.5,
        Geometry::Cuboid(_) => 2.5,
        Geometry::DrawDown(_) => 1.5,
        // The lift empties the cylinder through its whole foot: costed as a slot as wide as
        // the cylinder.
        Geometry::Heap(g) => return n * n / (2.0 * g.cylinder_radius).powf(1.5),
        Geometry::Mesh(g) => match g.outlet {
            MeshOutlet::Disc { .. } => 2.5,
            MeshOutlet::Rectangle { .. } => 1.5,
        },
    };
    n * n / opening.powf(exponent)
}

/// How a study runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StudyOptions {
    /// Cases run at the same time; 0 means one per available core.
    pub jobs: usize,
}

/// What the study reports while it runs (for progress bars and logs).
#[derive(Debug, Clone, PartialEq)]
pub enum StudyEvent {
    /// The plan is known: `total` cases, of which `already_done` finished in an earlier run.
    Started {
        /// Cases in the plan.
        total: usize,
        /// Cases whose summary was already on disk.
        already_done: usize,
    },
    /// One case ended (finished, clogged or failed).
    CaseEnded {
        /// Case identifier.
        id: String,
        /// Orifice width D [m].
        outlet_width: f64,
        /// Discharge rate W [kg/s] (NaN for a failed case).
        discharge_rate: f64,
        /// How it ended.
        status: CaseStatus,
        /// Wall-clock time of the run [s].
        wall_time: f64,
        /// The error of a failed case.
        reason: Option<String>,
        /// Cases finished so far, including earlier runs.
        done: usize,
        /// Cases in the plan.
        total: usize,
    },
}

/// What a study run did.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyOutcome {
    /// Every row of `results.csv`, sorted by identifier.
    pub rows: Vec<ResultRow>,
    /// Cases run in this invocation.
    pub ran: usize,
    /// Cases skipped because an earlier run finished them.
    pub reused: usize,
    /// Cases that failed in this invocation.
    pub failures: Vec<CaseFailure>,
}

/// Saves a summary the runner returned but did not save, so that the case counts as finished
/// on a restart, and returns it as read back from disk: JSON parsing may differ from the
/// in-memory value in the last bit, and the table of a resumed (or collected) study must
/// equal an uninterrupted one.
pub(crate) fn keep_summary(dir: &Path, summary: CaseSummary) -> Result<CaseSummary, String> {
    let path = dir.join(SUMMARY_FILE);
    if !path.exists() {
        write_json_atomic(&path, &summary).map_err(|e| e.to_string())?;
    }
    Ok(finished_summary(dir).unwrap_or(summary))
}

/// Reads a finished case's summary; `None` when it is absent or unreadable (then the case
/// is run again: summaries are written atomically, so an unreadable one is not ours).
pub(crate) fn finished_summary(dir: &Path) -> Option<CaseSummary> {
    let text = std::fs::read_to_string(dir.join(SUMMARY_FILE)).ok()?;
    serde_json::from_str(&text).ok()
}

pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_string()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Mutable state shared by the workers.
struct Progress {
    rows: BTreeMap<String, ResultRow>,
    failures: BTreeMap<String, CaseFailure>,
    done: usize,
    first_error: Option<StudyError>,
}

/// Whether `study.json` in `paths`, if there is one, belongs to `plan` (same sweep name and
/// config hash); returns whether there is one.
pub(crate) fn same_study(plan: &SweepPlan, paths: &StudyPaths) -> Result<bool, StudyError> {
    let Some(old) = StudyManifest::read(&paths.manifest())? else {
        return Ok(false);
    };
    let manifest = super::manifest_of_plan(plan);
    if old.name != manifest.name || old.config_hash != manifest.config_hash {
        return Err(StudyError::DifferentStudy {
            path: paths.manifest(),
            found_name: old.name,
            found_hash: old.config_hash,
            expected_name: manifest.name,
            expected_hash: manifest.config_hash,
        });
    }
    Ok(true)
}

/// Checks, reading only, that `plan` may run into `root`: its case identifiers are unique,
/// `study.json` (if any) belongs to the same sweep (name and config hash), and no case
/// folder holds a summary, checkpoint or case file of other inputs or a damaged one
/// ([`run::check_run_dir`]). A study refused here has changed nothing.
pub fn check_study_dir(plan: &SweepPlan, root: &Path) -> Result<(), StudyError> {
    let paths = StudyPaths::new(root);
    let mut seen = std::collections::BTreeSet::new();
    for case in &plan.cases {
        if !seen.insert(case.id.as_str()) {
            return Err(StudyError::DuplicateCase(case.id.clone()));
        }
    }
    if !root.is_dir() {
        // Nothing there to continue or to mix with (creating it may still fail).
        return Ok(());
    }
    same_study(plan, &paths)?;
    for case in &plan.cases {
        let dir = paths.case_dir(&case.id);
        run::check_run_dir_started(&case.case, &dir, plan.start.as_ref()).map_err(|source| {
            StudyError::CaseFolder {
                id: case.id.clone(),
                source: Box::new(source),
            }
        })?;
    }
    Ok(())
}

/// Runs `plan` into `root` with `runner`, skipping finished cases, and reports progress
/// through `observer`.
///
/// Refuses, before writing anything, what [`check_study_dir`] refuses: a directory of a
/// different sweep, or a case folder of other inputs, so that results of different inputs
/// are never mixed or mislabelled.
pub fn run_study(
    plan: &SweepPlan,
    root: &Path,
    runner: &dyn CaseRunner,
    options: &StudyOptions,
    observer: &(dyn Fn(&StudyEvent) + Sync),
) -> Result<StudyOutcome, StudyError> {
    let paths = StudyPaths::new(root);
    check_study_dir(plan, root)?;
    let cases_dir = root.join("cases");
    std::fs::create_dir_all(&cases_dir).map_err(|e| StudyError::io(&cases_dir, e))?;
    let manifest = super::manifest_of_plan(plan);
    manifest.write(&paths.manifest())?;

    let mut rows = BTreeMap::new();
    let mut pending = Vec::new();
    for case in &plan.cases {
        match finished_summary(&paths.case_dir(&case.id)) {
            Some(summary) => {
                rows.insert(case.id.clone(), super::measured_row(case, &summary));
            }
            None => pending.push(case),
        }
    }
    // Longest first, so that no worker is left with a long case while the others idle.
    // Only the order of execution changes; every case's results and the tables do not.
    pending.sort_by(|a, b| expected_cost(&b.case).total_cmp(&expected_cost(&a.case)));
    let reused = rows.len();
    write_results_table(&paths.results(), &rows)?;
    let total = plan.cases.len();
    observer(&StudyEvent::Started {
        total,
        already_done: reused,
    });

    let progress = Mutex::new(Progress {
        rows,
        failures: BTreeMap::new(),
        done: reused,
        first_error: None,
    });
    let next = AtomicUsize::new(0);
    let available = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = if options.jobs == 0 {
        available
    } else {
        options.jobs
    };
    let workers = jobs.min(pending.len()).max(1);

    let run_one = |case: &SweepCase| {
        let dir = paths.case_dir(&case.id);
        let started = Instant::now();
        let result = match std::fs::create_dir_all(&dir) {
            Err(e) => Err(format!("cannot create {}: {e}", dir.display())),
            Ok(()) => catch_unwind(AssertUnwindSafe(|| runner.run(case, &dir))).unwrap_or_else(
                |payload| Err(format!("the run panicked: {}", panic_message(&*payload))),
            ),
        };
        let result = result.and_then(|summary| keep_summary(&dir, summary));
        let wall_time = started.elapsed().as_secs_f64();
        let (row, reason) = match result {
            Ok(summary) => (super::measured_row(case, &summary), None),
            Err(reason) => (super::failed_row(case), Some(reason)),
        };
        let mut state = progress.lock().unwrap_or_else(|p| p.into_inner());
        state.done += 1;
        if let Some(reason) = &reason {
            state.failures.insert(
                case.id.clone(),
                CaseFailure {
                    id: case.id.clone(),
                    reason: reason.clone(),
                },
            );
        }
        let event = StudyEvent::CaseEnded {
            id: case.id.clone(),
            outlet_width: row.outlet_width,
            discharge_rate: row.discharge_rate,
            status: row.status,
            wall_time,
            reason,
            done: state.done,
            total,
        };
        state.rows.insert(case.id.clone(), row);
        let written = write_results_table(&paths.results(), &state.rows)
            .map_err(StudyError::from)
            .and_then(|()| {
                let failures: Vec<&CaseFailure> = state.failures.values().collect();
                write_json_atomic(paths.failures(), &failures).map_err(StudyError::from)
            });
        if let Err(e) = written {
            state.first_error.get_or_insert(e);
        }
        observer(&event);
    };

    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                let Some(case) = pending.get(index) else {
                    break;
                };
                run_one(case);
            });
        }
    });

    let state = progress.into_inner().unwrap_or_else(|p| p.into_inner());
    if let Some(error) = state.first_error {
        return Err(error);
    }
    let failures: Vec<CaseFailure> = state.failures.into_values().collect();
    write_results_table(&paths.results(), &state.rows)?;
    write_json_atomic(paths.failures(), &failures)?;
    Ok(StudyOutcome {
        rows: state.rows.into_values().collect(),
        ran: pending.len(),
        reused,
        failures,
    })
}
