//! Studies: a built-in sweep or a sweep file, run case by case as `hopperflow study` runs
//! them, with the GIL released and Ctrl-C checkpointing the running cases.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use case::{builtin_sweep, parse_sweep, SweepPlan, BUILTIN_SWEEP_NAMES};
use files::CaseStatus;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use run::Start;
use study::{SimulationRunner, StudyEvent, StudyOptions};

use crate::errors::{case_error, RunError};
use crate::run::{checked_threads, panic_text};

/// Most replicas accepted: each is a whole run of every grid point.
const MAX_REPLICAS: i64 = 1000;

const POLL: Duration = Duration::from_millis(50);

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
    let events: Arc<Mutex<Vec<(usize, usize, String)>>> = Arc::new(Mutex::new(Vec::new()));
    let sink = Arc::clone(&events);
    let skipped: Vec<(String, String)> = plan
        .skipped
        .iter()
        .map(|s| (s.id.clone(), s.reasons.join("; ")))
        .collect();
    let (tx, rx) = mpsc::channel();
    // Behind a mutex so that the waiting closure, which runs without the GIL, is `Send`.
    let rx = Mutex::new(rx);
    let root = out.clone();
    let worker = std::thread::Builder::new()
        .name("hopperflow-study".into())
        .spawn(move || {
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
                        let what = match status {
                            CaseStatus::Complete => format!("W = {:.1} g/s", discharge_rate * 1e3),
                            CaseStatus::Clogged => {
                                format!("CLOGGED (W before = {:.1} g/s)", discharge_rate * 1e3)
                            }
                            CaseStatus::Failed => {
                                format!("FAILED: {}", reason.as_deref().unwrap_or("unknown error"))
                            }
                        };
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
                sink.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            };
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                study::run_study(&plan, &root, &runner, &options, &observer)
            }));
            let _ = tx.send(result);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the study's thread: {e}")))?;

    let mut interrupt: Option<PyErr> = None;
    let result = loop {
        match py.detach(|| {
            rx.lock()
                .unwrap_or_else(|e| e.into_inner())
                .recv_timeout(POLL)
        }) {
            Ok(result) => break result,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                break Err(Box::new("the study's thread ended without a result")
                    as Box<dyn std::any::Any + Send>)
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if interrupt.is_some() {
            continue;
        }
        let lines: Vec<_> = std::mem::take(&mut *events.lock().unwrap_or_else(|e| e.into_inner()));
        if let Some(callback) = &progress {
            for line in lines {
                if let Err(e) = callback.call1(py, line) {
                    stop.store(true, Ordering::SeqCst);
                    interrupt = Some(e);
                    break;
                }
            }
        }
        if interrupt.is_none() {
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::SeqCst);
                interrupt = Some(e);
            }
        }
    };
    let _ = py.detach(|| worker.join());
    let outcome = result.map_err(|payload| {
        PyRuntimeError::new_err(format!(
            "internal error in the study: {}",
            panic_text(payload.as_ref())
        ))
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(callback) = &progress {
        for line in std::mem::take(&mut *events.lock().unwrap_or_else(|e| e.into_inner())) {
            callback.call1(py, line)?;
        }
    }
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
