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
