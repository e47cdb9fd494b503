//! Runs a case on a thread of its own with the GIL released, as `hopperflow run` does.
//!
//! The calling thread waits for it in short slices without the GIL, and between slices
//! takes the GIL to hand the latest progress to Python and to check for signals. A
//! KeyboardInterrupt (Ctrl-C, a notebook's "interrupt") sets the run's stop flag: the run
//! writes its checkpoint after the current protocol chunk, and the interrupt is raised
//! again once it has, so that `resume=True` continues the run bit-identically.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::exceptions::{PyFileExistsError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use run::{
    check_save_bed, occupant, read_bed, Occupant, Progress, RunError, RunOptions, RunOutcome,
    Start, StartError,
};

use crate::case::Case;
use crate::errors::RunError as PyRunError;

/// Most worker threads accepted: more would only ask the system for threads it then
/// refuses (results never depend on the count).
pub const MAX_THREADS: i64 = 1024;

/// How often the waiting thread looks at signals and progress.
const POLL: Duration = Duration::from_millis(50);

/// The engine's worker threads, checked: 1 to `MAX_THREADS`.
pub fn checked_threads(threads: i64) -> PyResult<usize> {
    if !(1..=MAX_THREADS).contains(&threads) {
        return Err(PyValueError::new_err(format!(
            "threads = {threads}: must be an integer in 1..={MAX_THREADS} \
             (worker threads of the engine; results are identical for any value)"
        )));
    }
    Ok(threads as usize)
}

/// Refuses an output directory that already holds a run, finished or checkpointed, when
/// neither `resume` nor `restart` says what to do with it (as the command line does).
fn refuse_occupied(out: &Path) -> PyResult<()> {
    match occupant(out) {
        None => Ok(()),
        Some(Occupant::Finished) => Err(PyFileExistsError::new_err(format!(
            "{} already holds a finished run; resume=True reads it back, restart=True runs \
             the case again, or choose another out",
            out.display()
        ))),
        Some(Occupant::Checkpoint(what)) => Err(PyFileExistsError::new_err(format!(
            "{} holds {what}; resume=True continues it, restart=True discards it, or choose \
             another out",
            out.display()
        ))),
    }
}

/// The Python exception of a failed run.
pub fn run_error(e: &RunError) -> PyErr {
    match e {
        RunError::OtherInputs { .. }
        | RunError::BadCheckpoint { .. }
        | RunError::BadSummary { .. } => PyValueError::new_err(format!(
            "{e}; restart=True discards what the folder holds and starts the case over"
        )),
        _ => PyRunError::new_err(e.to_string()),
    }
}

/// The text of a panic payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// What the run starts from, checked against `case` as `hopperflow run` checks it: a saved
/// bed (`from_bed`), a packing file (`packing`), or the fill.
fn start_of(
    case: &case::Case,
    from_bed: Option<PathBuf>,
    packing: Option<PathBuf>,
) -> PyResult<Start> {
    let refuse = |e: &dyn std::fmt::Display| PyValueError::new_err(e.to_string());
    if from_bed.is_some() && packing.is_some() {
        return Err(refuse(&StartError::BedAndPacking));
    }
    let bed = from_bed
        .map(|dir| read_bed(&dir).map_err(|e| refuse(&e)))
        .transpose()?;
    Start::choose(case, bed, packing.as_deref()).map_err(|e| refuse(&e))
}

/// The resolved case text of the bed in `dir` (`bed.bin` in it, or the file), for a run from
/// a bed that gives no case of its own: the bed's case is then its base.
#[pyfunction]
pub fn bed_case_text(dir: PathBuf) -> PyResult<String> {
    read_bed(&dir)
        .map(|bed| bed.case_text().to_string())
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The cost estimate of running `case` (`hopperflow run --estimate --json`), as JSON text:
/// spheres, time step, simulated time, steps, particle-steps and wall time by part of the
/// protocol (the settling and the discharge at most, and `likely`), the engine's speed timed
/// on this machine, peak memory, and why the command line would refuse the run (`refusal`,
/// or null).
#[pyfunction]
#[pyo3(signature = (case, threads = 1, from_bed = None, packing = None))]
pub fn estimate_cost(
    py: Python<'_>,
    case: PyRef<'_, Case>,
    threads: i64,
    from_bed: Option<PathBuf>,
    packing: Option<PathBuf>,
) -> PyResult<String> {
    let threads = checked_threads(threads)?;
    let start = start_of(&case.case, from_bed, packing)?;
    let case = case.case.clone();
    let estimate = py
        .detach(|| run::cost::estimate_cost(&case, &start, threads, run::cost::Timing::Always))
        .map_err(|e| PyRuntimeError::new_err(format!("the cost could not be estimated: {e}")))?;
    let physical = run::cost::physical_memory();
    let refusal = run::cost::cost_refusal(&case, &estimate, physical);
    let mut value =
        serde_json::to_value(&estimate).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    value["wall_time_total_s"] = estimate.wall_time.total().into();
    value["likely_wall_time_total_s"] = estimate.likely.wall_time.total().into();
    value["physical_memory"] = physical.into();
    value["max_wall_time_s"] = run::cost::MAX_WALL_TIME.into();
    value["refusal"] = refusal.into();
    Ok(value.to_string())
}

/// Runs `case` into `out`; returns "finished", or raises KeyboardInterrupt after writing a
/// checkpoint when interrupted. `progress(phase, time, particles, fraction, rate)` is
/// called with the latest progress a few times a second. `from_bed`, `packing` and
/// `save_bed` are `hopperflow run`'s `--from-bed`, `--packing` and `--save-bed`.
#[pyfunction]
#[pyo3(signature = (case, out, threads = 1, resume = false, restart = false, pictures = true, progress = None, from_bed = None, packing = None, save_bed = None))]
#[allow(clippy::too_many_arguments)]
pub fn run_case(
    py: Python<'_>,
    case: PyRef<'_, Case>,
    out: PathBuf,
    threads: i64,
    resume: bool,
    restart: bool,
    pictures: bool,
    progress: Option<Py<PyAny>>,
    from_bed: Option<PathBuf>,
    packing: Option<PathBuf>,
    save_bed: Option<PathBuf>,
) -> PyResult<&'static str> {
    let threads = checked_threads(threads)?;
    if resume && restart {
        return Err(PyValueError::new_err(
            "resume=True and restart=True exclude each other: resume continues what the \
             folder holds, restart discards it",
        ));
    }
    // Every input is checked before the output folder is touched.
    let start = start_of(&case.case, from_bed, packing)?;
    if !resume && !restart {
        refuse_occupied(&out)?;
    }
    if let Some(dir) = &save_bed {
        check_save_bed(dir, &case.case, resume, restart)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
    }
    let case = case.case.clone();
    let stop = Arc::new(AtomicBool::new(false));
    let latest: Arc<Mutex<Option<Progress>>> = Arc::new(Mutex::new(None));
    let sink_latest = Arc::clone(&latest);
    let options = RunOptions {
        threads,
        resume: !restart,
        progress: Some(Arc::new(move |p: &Progress| {
            *sink_latest.lock().unwrap_or_else(|e| e.into_inner()) = Some(*p);
        })),
        pictures,
        chunk_limit: None,
        stop: Some(Arc::clone(&stop)),
        save_bed,
    };
    let (done_tx, done_rx) = mpsc::channel();
    // Behind a mutex so that the waiting closure, which runs without the GIL, is `Send`.
    let done_rx = Mutex::new(done_rx);
    let worker = std::thread::Builder::new()
        .name("hopperflow-run".into())
        .spawn(move || {
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run::run_case_from(&case, &out, &options, &start)
            }));
            let _ = done_tx.send(result);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the run's thread: {e}")))?;

    let mut interrupt: Option<PyErr> = None;
    let result = loop {
        let received = py.detach(|| {
            done_rx
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .recv_timeout(POLL)
        });
        match received {
            Ok(result) => break result,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                break Err(Box::new("the run's thread ended without a result")
                    as Box<dyn std::any::Any + Send>)
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if interrupt.is_some() {
            continue;
        }
        let report = latest.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let (Some(p), Some(callback)) = (report, &progress) {
            let call = callback.call1(
                py,
                (
                    p.phase,
                    p.time,
                    p.particles,
                    p.fraction,
                    p.particle_steps_per_second,
                ),
            );
            if let Err(e) = call {
                // A failing progress callback stops the run like an interrupt would.
                stop.store(true, Ordering::SeqCst);
                interrupt = Some(e);
                continue;
            }
        }
        if let Err(e) = py.check_signals() {
            stop.store(true, Ordering::SeqCst);
            interrupt = Some(e);
        }
    };
    let _ = py.detach(|| worker.join());
    let outcome = match result {
        Ok(outcome) => outcome,
        Err(payload) => {
            return Err(PyRuntimeError::new_err(format!(
                "internal error in the run: {}",
                panic_text(payload.as_ref())
            )))
        }
    };
    match (outcome, interrupt) {
        (Ok(RunOutcome::Finished(_)), None) => Ok("finished"),
        (Ok(RunOutcome::Interrupted), None) => Ok("interrupted"),
        // The run ended (finished or checkpointed); the interrupt goes on to the caller.
        (Ok(_), Some(e)) => Err(e),
        (Err(e), _) => Err(run_error(&e)),
    }
}
