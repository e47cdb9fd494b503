//! Calibration: `hopperflow calibrate` from Python, with the GIL released and Ctrl-C
//! checkpointing the running cases.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use calibrate::{run_calibration, CalibrationError, CalibrationEvent, CalibrationOptions};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use run::Start;
use study::{SimulationRunner, StudyEvent};

use crate::errors::{case_error, RunError};
use crate::run::panic_text;

const POLL: Duration = Duration::from_millis(50);

/// Runs (or continues) the calibration file `file` into `out`. `progress(done, total,
/// line)` is called as runs end (done and total count the current round's runs) and after
/// each round's fit. Returns `out`'s calibration.json as text. Raises CaseError for a bad
/// calibration file or test case, ValueError for a folder of another calibration,
/// RunError when the calibration cannot go on, KeyboardInterrupt once the running cases
/// have checkpointed.
#[pyfunction]
#[pyo3(signature = (file, out, jobs = 0, progress = None))]
pub fn run_calibration_file(
    py: Python<'_>,
    file: PathBuf,
    out: PathBuf,
    jobs: i64,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    if !(0..=1024).contains(&jobs) {
        return Err(PyValueError::new_err(format!(
            "jobs = {jobs}: must be an integer in 0..=1024 (runs at once; 0 = one per core)"
        )));
    }
    let plan = case::load_calibration(&file).map_err(|e| case_error(py, &e))?;
    let stop = Arc::new(AtomicBool::new(false));
    let runner = SimulationRunner {
        pictures: false,
        stop: Some(Arc::clone(&stop)),
        threads: 1,
        start: Arc::new(Start::Fill),
    };
    let events: Arc<Mutex<Vec<(usize, usize, String)>>> = Arc::new(Mutex::new(Vec::new()));
    let sink = Arc::clone(&events);
    let (tx, rx) = mpsc::channel();
    let rx = Mutex::new(rx);
    let root = out.clone();
    let flag = Arc::clone(&stop);
    let worker = std::thread::Builder::new()
        .name("hopperflow-calibration".into())
        .spawn(move || {
            let observer = move |event: CalibrationEvent<'_>| {
                let line = match event {
                    CalibrationEvent::RoundStarted { round, runs, .. } => {
                        (0, runs, format!("round {round}: {runs} runs"))
                    }
                    CalibrationEvent::Study(StudyEvent::Started {
                        total,
                        already_done,
                    }) => (
                        *already_done,
                        *total,
                        format!("{already_done} of {total} runs already finished"),
                    ),
                    CalibrationEvent::Study(StudyEvent::CaseEnded {
                        id, done, total, ..
                    }) => (*done, *total, id.clone()),
                    CalibrationEvent::RoundFitted(round) => {
                        let estimate: Vec<String> = round
                            .estimate
                            .iter()
                            .map(|e| {
                                format!("{} = {:.4e} ± {:.1e}", e.key, e.value, e.standard_error)
                            })
                            .collect();
                        (
                            round.runs,
                            round.runs,
                            format!("round {}: {}", round.round, estimate.join(", ")),
                        )
                    }
                };
                sink.lock().unwrap_or_else(|e| e.into_inner()).push(line);
            };
            let options = CalibrationOptions {
                jobs: jobs as usize,
            };
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run_calibration(&plan, &root, &runner, &options, &observer, Some(&flag))
            }));
            let _ = tx.send(result);
        })
        .map_err(|e| {
            PyRuntimeError::new_err(format!("cannot start the calibration's thread: {e}"))
        })?;

    let mut interrupt: Option<PyErr> = None;
    let result = loop {
        match py.detach(|| {
            rx.lock()
                .unwrap_or_else(|e| e.into_inner())
                .recv_timeout(POLL)
        }) {
            Ok(result) => break result,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                break Err(Box::new("the calibration's thread ended without a result")
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
            "internal error in the calibration: {}",
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
    match outcome {
        Ok(_) => std::fs::read_to_string(out.join(calibrate::CALIBRATION_FILE))
            .map_err(|e| RunError::new_err(e.to_string())),
        Err(CalibrationError::Case { source, .. }) => Err(case_error(py, &source)),
        Err(e @ CalibrationError::DifferentCalibration { .. }) => {
            Err(PyValueError::new_err(e.to_string()))
        }
        Err(e) => Err(RunError::new_err(e.to_string())),
    }
}
