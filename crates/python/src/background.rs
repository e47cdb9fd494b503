//! Long work (a study, a calibration) on a thread of its own while Python waits with the GIL
//! released: the work posts progress lines, which are handed to the caller's callable; Ctrl-C,
//! or an exception from that callable, sets the stop flag the work's runner checkpoints on,
//! and is raised once the work has stopped.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::run::panic_text;

/// How often the waiting thread looks at the signals and the progress lines.
const POLL: Duration = Duration::from_millis(50);

/// One progress line: (done, total, text), as `progress(done, total, line)` takes it.
pub type Line = (usize, usize, String);

/// The progress lines the work has posted and Python has not yet seen.
#[derive(Clone, Default)]
pub struct Lines(Arc<Mutex<Vec<Line>>>);

impl Lines {
    /// Posts a line (from the work's thread).
    pub fn push(&self, line: Line) {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).push(line);
    }

    fn take(&self) -> Vec<Line> {
        std::mem::take(&mut *self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// Runs `work` on a thread named `hopperflow-<what>` and waits for it with the GIL released,
/// handing `lines` to `progress` as they come. Ctrl-C or an exception from `progress` sets
/// `stop` and is raised once the work has returned; a panic in the work is a RuntimeError.
pub fn run_in_background<T: Send + 'static>(
    py: Python<'_>,
    what: &str,
    progress: Option<&Py<PyAny>>,
    stop: &AtomicBool,
    lines: &Lines,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = mpsc::channel();
    // Behind a mutex so that the waiting closure, which runs without the GIL, is `Send`.
    let rx = Mutex::new(rx);
    let worker = std::thread::Builder::new()
        .name(format!("hopperflow-{what}"))
        .spawn(move || {
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
            let _ = tx.send(result);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the {what}'s thread: {e}")))?;

    let mut interrupt: Option<PyErr> = None;
    let result = loop {
        match py.detach(|| {
            rx.lock()
                .unwrap_or_else(|e| e.into_inner())
                .recv_timeout(POLL)
        }) {
            Ok(result) => break result,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                break Err(
                    Box::new(format!("the {what}'s thread ended without a result"))
                        as Box<dyn std::any::Any + Send>,
                )
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if interrupt.is_some() {
            continue;
        }
        let posted = lines.take();
        if let Some(callback) = progress {
            for line in posted {
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
            "internal error in the {what}: {}",
            panic_text(payload.as_ref())
        ))
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(callback) = progress {
        for line in lines.take() {
            callback.call1(py, line)?;
        }
    }
    Ok(outcome)
}
