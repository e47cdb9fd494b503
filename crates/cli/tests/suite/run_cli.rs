//! Running the built `hopperflow` binary from the command-line tests.

// Each test file compiles its own copy of this module and uses what it needs of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `hopperflow` with `args` and waits for it.
pub fn hopperflow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopperflow"))
        .args(args)
        .output()
        .expect("the hopperflow binary starts")
}

/// A temporary path as an argument (the tests' folders have UTF-8 names).
pub fn utf8(path: &Path) -> &str {
    path.to_str().expect("UTF-8 test path")
}

/// The standard error of a finished command, as text.
pub fn stderr_of(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Asserts the exit status `expected` and no panic (Rust's panic exit status, 101, is never
/// an answer to bad input).
pub fn assert_status(output: &Output, expected: i32, what: &str) {
    let stderr = stderr_of(output);
    assert!(
        !stderr.contains("panicked"),
        "{what}: the binary panicked:\n{stderr}"
    );
    assert_eq!(
        output.status.code(),
        Some(expected),
        "{what}: wrong exit status; stderr:\n{stderr}"
    );
}

/// Asserts a refusal of bad input: exit status 2, no panic, and every fragment present in
/// standard error.
pub fn assert_refused(output: &Output, what: &str, fragments: &[&str]) {
    assert_status(output, 2, what);
    let stderr = stderr_of(output);
    for fragment in fragments {
        assert!(
            stderr.contains(fragment),
            "{what}: stderr lacks `{fragment}`; it reads:\n{stderr}"
        );
    }
}
