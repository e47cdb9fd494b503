//! Calibration: `hopperflow calibrate` from Python, with the GIL released and Ctrl-C
//! checkpointing the running cases.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use calibrate::{run_calibration, CalibrationError, CalibrationEvent, CalibrationOptions};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use run::Start;
use study::{SimulationRunner, StudyEvent};

use crate::background::{run_in_background, Lines};
use crate::errors::{case_error, RunError};

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
    let lines = Lines::default();
    let sink = lines.clone();
    let flag = Arc::clone(&stop);
    let root = out.clone();
    let work = move || {
        let observer = move |event: CalibrationEvent<'_>| {
            sink.push(match event {
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
                        .map(|e| format!("{} = {:.4e} ± {:.1e}", e.key, e.value, e.standard_error))
                        .collect();
                    (
                        round.runs,
                        round.runs,
                        format!("round {}: {}", round.round, estimate.join(", ")),
                    )
                }
            });
        };
        let options = CalibrationOptions {
            jobs: jobs as usize,
        };
        run_calibration(&plan, &root, &runner, &options, &observer, Some(&flag))
    };
    let outcome = run_in_background(py, "calibration", progress.as_ref(), &stop, &lines, work)?;
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
