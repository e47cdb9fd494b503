//! Studies: a built-in sweep or a sweep file, run case by case as `hopperflow study` runs
//! them, with the GIL released and Ctrl-C checkpointing the running cases.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use case::{builtin_sweep, parse_sweep, SweepPlan, BUILTIN_SWEEP_NAMES};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use run::Start;
use study::{SimulationRunner, StudyEvent, StudyOptions};

use crate::background::{run_in_background, Lines};
use crate::errors::{case_error, RunError};
use crate::run::checked_threads;

/// Most replicas accepted: each is a whole run of every grid point.
const MAX_REPLICAS: i64 = 1000;

/// The names of the built-in sweeps.
#[pyfunction]
pub fn builtin_sweeps() -> Vec<&'static str> {
    BUILTIN_SWEEP_NAMES.to_vec()
}

/// The sweep text and its plan, for a built-in name or a file.
fn plan(
    py: Python<'_>,
    sweep: &str,
    replicas: Option<i64>,
    sets: &[String],
) -> PyResult<(String, SweepPlan)> {
    let (text, name, base): (String, String, Option<PathBuf>) = match builtin_sweep(sweep) {
        Some(text) => (text.to_string(), sweep.to_string(), None),
        None => {
            let path = PathBuf::from(sweep);
            if !path.is_file() {
                return Err(PyValueError::new_err(format!(
                    "sweep = {sweep:?}: neither a built-in sweep ({}) nor a file",
                    BUILTIN_SWEEP_NAMES.join(", ")
                )));
            }
            let text = std::fs::read_to_string(&path)?;
            let base = path.parent().map(Path::to_path_buf);
            (text, sweep.to_string(), base)
        }
    };
    let text = match replicas {
        None => text,
        Some(r) if (1..=MAX_REPLICAS).contains(&r) => case::sweep_with_replicas(&text, r as u32),
        Some(r) => {
            return Err(PyValueError::new_err(format!(
                "replicas = {r}: must be an integer in 1..={MAX_REPLICAS} (independent fills per grid point)"
            )))
        }
    };
    let plan = parse_sweep(&text, &name, base.as_deref(), sets).map_err(|e| case_error(py, &e))?;
    Ok((text, plan))
}

/// Runs a study into `out`. Returns a dict: ran, reused, failed (ids), skipped (id and
/// reasons). `progress(done, total, line)` is called as cases end. Raises
/// KeyboardInterrupt once the running cases have written their checkpoints.
#[pyfunction]
#[pyo3(signature = (sweep, out, jobs = 0, replicas = None, sets = Vec::new(), case_threads = 1, pictures = false, progress = None, from_bed = None))]
#[allow(clippy::too_many_arguments)]
pub fn run_study<'py>(
    py: Python<'py>,
    sweep: &str,
    out: PathBuf,
    jobs: i64,
    replicas: Option<i64>,
    sets: Vec<String>,
    case_threads: i64,
    pictures: bool,
    progress: Option<Py<PyAny>>,
    from_bed: Option<PathBuf>,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    if !(0..=1024).contains(&jobs) {
        return Err(PyValueError::new_err(format!(
            "jobs = {jobs}: must be an integer in 0..=1024 (cases run at once; 0 = one per core)"
        )));
    }
    let threads = checked_threads(case_threads)?;
    let (text, plan) = plan(py, sweep, replicas, &sets)?;
    // A study from one bed (`hopperflow study --from-bed`): every case checked against it.
    let (plan, start) = match from_bed {
        None => (plan, Start::Fill),
        Some(dir) => study::plan_from_bed_dir(plan, &dir)
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
    };
    study::check_study_dir(&plan, &out).map_err(|e| PyValueError::new_err(e.to_string()))?;
    std::fs::create_dir_all(&out)?;
    files::write_atomic(out.join("sweep.toml"), text.as_bytes())
        .map_err(|e| RunError::new_err(e.to_string()))?;

    let stop = Arc::new(AtomicBool::new(false));
    let runner = SimulationRunner {
        pictures,
        stop: Some(Arc::clone(&stop)),
        threads,
        start: Arc::new(start),
    };
    let options = StudyOptions {
        jobs: jobs as usize,
    };
    let lines = Lines::default();
    let sink = lines.clone();
    let skipped: Vec<(String, String)> = plan
        .skipped
        .iter()
        .map(|s| (s.id.clone(), s.reasons.join("; ")))
        .collect();
    let work = move || {
        let observer = move |event: &StudyEvent| {
            let line = match event {
                StudyEvent::Started {
                    total,
                    already_done,
                } => (
                    *already_done,
                    *total,
                    format!("{already_done} of {total} cases already finished"),
                ),
                StudyEvent::CaseEnded {
                    id,
                    outlet_width,
                    discharge_rate,
                    status,
                    wall_time,
                    reason,
                    done,
                    total,
                } => {
                    let what = status.outcome_words(*discharge_rate, reason.as_deref());
                    (
                        *done,
                        *total,
                        format!(
                            "{id} D = {:.1} mm {what} ({wall_time:.0} s)",
                            outlet_width * 1e3
                        ),
                    )
                }
            };
            sink.push(line);
        };
        study::run_study(&plan, &out, &runner, &options, &observer)
    };
    let outcome = run_in_background(py, "study", progress.as_ref(), &stop, &lines, work)?;
    let outcome = outcome.map_err(|e| RunError::new_err(e.to_string()))?;
    let d = pyo3::types::PyDict::new(py);
    d.set_item("ran", outcome.ran)?;
    d.set_item("reused", outcome.reused)?;
    let failed: Vec<(String, String)> = outcome
        .failures
        .iter()
        .map(|f| (f.id.clone(), f.reason.clone()))
        .collect();
    d.set_item("failed", failed)?;
    d.set_item("skipped", skipped)?;
    Ok(d)
}

/// Builds the report of the study in `root`; returns the paths of its files.
#[pyfunction]
pub fn study_report(root: PathBuf) -> PyResult<Vec<PathBuf>> {
    let files = report::build_report(&root).map_err(|e| RunError::new_err(e.to_string()))?;
    let mut paths = vec![files.markdown, files.html, files.comparison];
    paths.extend(files.figures);
    Ok(paths)
}
