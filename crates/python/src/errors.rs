//! The exceptions of the module and how Rust errors become them.

use case::{ConfigError, ConfigErrors};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

create_exception!(
    _native,
    CaseError,
    PyValueError,
    "A case or sweep that cannot be used: `.key`, `.line`, `.value` and `.message` describe \
     the first problem, `.errors` lists every one; `str()` is the command line's text."
);
create_exception!(
    _native,
    RunError,
    PyRuntimeError,
    "A run or study that stopped with an error (the engine, a probe, an output file)."
);

/// A `CaseError` carrying every problem of `errors`, with the CLI's text as its message.
pub fn case_error(py: Python<'_>, errors: &ConfigErrors) -> PyErr {
    let err = CaseError::new_err(errors.to_string());
    if let Err(e) = describe(py, &err, &errors.errors) {
        return e;
    }
    err
}

/// A `CaseError` about one key, for values that cannot even be written as TOML.
pub fn key_error(py: Python<'_>, key: &str, value: Option<String>, message: &str) -> PyErr {
    let error = ConfigError::new(
        case::ErrorKind::WrongType,
        case::Location::whole(&std::sync::Arc::from("python")),
        key,
        value,
        message,
    );
    case_error(py, &ConfigErrors::single(error))
}

/// Sets `.key`, `.line`, `.column`, `.value`, `.message`, `.source`, `.kind` (of the first
/// error) and `.errors` (all of them, as dicts) on the exception.
fn describe(py: Python<'_>, err: &PyErr, errors: &[ConfigError]) -> PyResult<()> {
    let value = err.value(py);
    let list = errors
        .iter()
        .map(|e| error_dict(py, e))
        .collect::<PyResult<Vec<_>>>()?;
    let first = list.first().cloned();
    value.setattr("errors", list)?;
    for name in [
        "key", "line", "column", "value", "message", "source", "kind",
    ] {
        let item = match &first {
            Some(d) => d.get_item(name)?,
            None => None,
        };
        value.setattr(name, item)?;
    }
    Ok(())
}

fn error_dict<'py>(py: Python<'py>, e: &ConfigError) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("key", &e.key)?;
    d.set_item("line", e.location.line)?;
    d.set_item("column", e.location.column)?;
    d.set_item("value", &e.value)?;
    d.set_item("message", &e.message)?;
    d.set_item("source", &*e.location.source)?;
    d.set_item("kind", format!("{:?}", e.kind))?;
    d.set_item("text", format!("error: {e}"))?;
    Ok(d)
}
