//! Python bindings of hopperflow: the extension module `hopperflow._native`.
//!
//! The Python package (`python/hopperflow`) wraps this module: it turns the files of a run
//! into numpy arrays or pandas tables and draws progress. This module holds what needs the
//! Rust crates: validated cases (`case`), runs with the GIL released (`run`), studies
//! (`studies`) and the engine itself (`engine`).
//!
//! No Rust panic may reach Python: every input is checked before it reaches the engine, and
//! the work that runs on threads of its own returns a panic as a `RuntimeError`.

mod background;
mod calibration;
mod case;
mod engine;
mod errors;
mod run;
mod studies;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("CaseError", py.get_type::<errors::CaseError>())?;
    m.add("RunError", py.get_type::<errors::RunError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<case::Case>()?;
    m.add_class::<engine::Simulation>()?;
    m.add_function(wrap_pyfunction!(case::overrides_of, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_case, m)?)?;
    m.add_function(wrap_pyfunction!(run::estimate_cost, m)?)?;
    m.add_function(wrap_pyfunction!(run::bed_case_text, m)?)?;
    m.add_function(wrap_pyfunction!(engine::engine_reference, m)?)?;
    m.add_function(wrap_pyfunction!(studies::run_study, m)?)?;
    m.add_function(wrap_pyfunction!(calibration::run_calibration_file, m)?)?;
    m.add_function(wrap_pyfunction!(studies::study_report, m)?)?;
    m.add_function(wrap_pyfunction!(studies::builtin_sweeps, m)?)?;
    Ok(())
}
